// hfts-server: the planning service (docs/protocol.md). Loads the robots,
// their hand maps, the object databases and the scenes, prints
// "hfts-server listening on ADDRESS:PORT" on standard output and serves
// until a shutdown call, SIGINT or SIGTERM (SIGHUP re-reads the token file of
// --auth-tokens). One log line per request on standard error.
#include <CLI/CLI.hpp>

#include <iostream>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "service/server.h"

int main(int argc, char** argv) {
  hfts::service::ServerOptions o;
  o.sources.database_dir = "build/databases";
  o.port = 7450;  // hfts-client's default too
  std::vector<std::string> robots;
  std::string db = o.sources.database_dir.string(), scenes = o.sources.scene_dir.string();
  double maxMessageMiB = static_cast<double>(o.max_message_bytes) / (1 << 20);
  double maxBufferedMiB = static_cast<double>(o.max_buffered_bytes) / (1 << 20);
  bool quiet = false;
  CLI::App app{"hfts-server: grasp and motion planning over TCP JSON-RPC 2.0 (docs/protocol.md)"};
  app.add_option("--robot", robots,
                 "Robot config; repeat it to serve several robots (a plan's \"robot\" names "
                 "one, default the first) [default: " +
                     o.sources.robot_configs.front().string() + "]")
      ->take_all()
      ->expected(1)
      ->allow_extra_args(false);
  app.add_option("--db", db, "Object databases and every robot's hand map")->capture_default_str();
  app.add_option("--scenes", scenes, "Scene files (*.json)")->capture_default_str();
  app.add_option("--bind", o.bind_address, "Address to listen on")->capture_default_str();
  app.add_option("--port", o.port, "TCP port; 0 picks a free one")->capture_default_str();
  app.add_option("--workers", o.workers, "Planning threads; 0: one per core")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--queue", o.queue_capacity, "Plans that may wait for a worker")
      ->capture_default_str();
  app.add_option("--max-plans-per-client", o.max_plans_per_client,
                 "Plans one client (a token; without tokens a connection) may have queued or "
                 "running at once; 0: no cap")
      ->capture_default_str();
  app.add_option("--max-time-limit", o.max_time_limit, "Largest plan time_limit (s)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--max-message-mib", maxMessageMiB, "Largest message (MiB)")
      ->check(CLI::Range(0.001, 1024.0))
      ->capture_default_str();
  app.add_option("--max-connections", o.max_connections,
                 "Connections open at once; one more gets error -32006 and is closed")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--max-buffered-mib", maxBufferedMiB,
                 "Input of unfinished messages the server holds beyond 64 KiB per connection "
                 "(MiB); a message that does not fit gets error -32007")
      ->check(CLI::Range(1.0, 1048576.0))
      ->capture_default_str();
  app.add_option("--read-timeout", o.read_timeout,
                 "Seconds to finish a begun message, else error -32008 (0: none)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option("--idle-timeout", o.idle_timeout,
                 "Seconds a connection may stay silent with no call pending, else error -32008 "
                 "(0: none)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  std::string tokens;
  app.add_option("--auth-tokens", tokens,
                 "Token file: one 'ROLE TOKEN [NAME]' per line, ROLE plan or admin; not readable "
                 "by every user; re-read on SIGHUP (docs/security.md)");
  app.add_flag("--insecure", o.insecure,
               "Listen on a non-loopback address without --auth-tokens (anyone who reaches the "
               "port may plan, reload and shut the server down)");
  std::string tlsCert, tlsKey;
  app.add_option("--tls-cert", tlsCert,
                 "Speak TLS with this PEM certificate chain (with --tls-key; docs/security.md)");
  app.add_option("--tls-key", tlsKey, "The PEM private key of --tls-cert");
  app.add_flag("--quiet", quiet, "No request log on standard error");
  CLI11_PARSE(app, argc, argv);

#if defined(__GLIBC__)
  // Blocks of 128 KiB and more (large messages) get their own mappings,
  // which free() returns to the system; glibc's default threshold rises
  // after such frees and would keep them in the heap (docs/reliability.md).
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif

  o.sources.database_dir = db;
  o.sources.scene_dir = scenes;
  if (!robots.empty()) o.sources.robot_configs.assign(robots.begin(), robots.end());
  o.max_message_bytes = static_cast<std::size_t>(maxMessageMiB * (1 << 20));
  o.max_buffered_bytes = static_cast<std::size_t>(maxBufferedMiB * (1 << 20));
  o.log = quiet ? nullptr : &std::cerr;
  o.auth_tokens = tokens;
  o.tls_cert = tlsCert;
  o.tls_key = tlsKey;
  if (o.insecure && tokens.empty())
    std::cerr << "hfts-server: warning: --insecure: no authentication; anyone who reaches "
              << o.bind_address << ":" << o.port << " may plan, reload and shut the server down\n";
  try {
    hfts::service::Server server(o);
    for (const std::string& why : server.initialCatalog().skipped())
      std::cerr << "hfts-server: skipped " << why << "\n";
    std::cout << "hfts-server listening on " << o.bind_address << ":" << server.port() << std::endl;
    server.run();
  } catch (const std::exception& e) {
    std::cerr << "hfts-server: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
