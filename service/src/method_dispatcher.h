#pragma once
// Runs the calls of every connection: validates them, answers the quick
// methods at once, queues plans on the worker pool, and logs one line per
// call. Used only on the server's I/O thread.

#include <nlohmann/json.hpp>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "cancel_registry.h"
#include "json_rpc.h"
#include "request_log.h"
#include "service/access_tokens.h"
#include "service/plan_request_json.h"
#include "service/planning_catalog.h"
#include "service/server_options.h"
#include "worker_pool.h"

namespace hfts::service {

/// What a connection has proven about itself (docs/security.md).
struct Session {
  /// The digest of the token it authenticated with; its role is looked up
  /// again on every call, so a token taken out of the file (SIGHUP) stops
  /// working at once.
  std::optional<TokenDigest> token;
  /// A failed auth: the connection reads nothing more and closes once the
  /// reply is written.
  bool close_after_reply = false;
};

/// The connection a call came from.
struct Caller {
  std::string peer;                       ///< "address:port", for the log
  std::string address;                    ///< the peer's address alone (the auth throttle)
  std::shared_ptr<CancelRegistry> plans;  ///< the connection's cancellable plans
  std::shared_ptr<Session> session = std::make_shared<Session>();
};

/// Receives the response of one call (null for a notification). Always
/// called exactly once, on the I/O thread.
using Responder = std::function<void(nlohmann::json response)>;

/// Runs a function on the I/O thread (asio::post), after a delay when
/// one is given.
using PostToIo = std::function<void(std::function<void()>)>;
using PostAfter = std::function<void(std::chrono::milliseconds, std::function<void()>)>;

/// How long the reply to a failed auth is held back: a guesser gets one try
/// per connection and per this much time.
inline constexpr std::chrono::milliseconds kAuthFailureDelay{1000};

/// The connections' share of server.info's "load" (the server knows it).
struct ConnectionLoad {
  std::size_t connections = 0;
  std::size_t input_budget_used = 0;  ///< bytes of InputBudget taken
};

class MethodDispatcher {
 public:
  /// `onShutdown` is called (on the I/O thread) after a `shutdown` call
  /// has been answered. `tokens` null: no authentication, every connection
  /// may call every method (a server bound to loopback, or --insecure).
  MethodDispatcher(const ServerOptions& options, std::shared_ptr<const PlanningCatalog> catalog,
                   std::shared_ptr<const TokenTable> tokens, PostToIo post, PostAfter postAfter,
                   std::function<void()> onShutdown);
  ~MethodDispatcher();
  MethodDispatcher(const MethodDispatcher&) = delete;
  MethodDispatcher& operator=(const MethodDispatcher&) = delete;

  void dispatch(const Call& call, const Caller& caller, Responder respond);
  /// The tokens from now on (a SIGHUP re-read the file); a connection whose
  /// token is no longer there must authenticate again.
  void setTokens(std::shared_ptr<const TokenTable> tokens) { tokens_ = std::move(tokens); }
  /// Where server.info reads the connection figures of "load".
  void setConnectionLoad(std::function<ConnectionLoad()> load) {
    connection_load_ = std::move(load);
  }
  /// Logs the error response to a message or batch element that held no
  /// valid call (parse error, invalid request, oversized message).
  void logRejected(const Caller& caller, const nlohmann::json& errorResponse) const;

  /// From now on new calls are refused; queued and running plans are cancelled.
  void stop();
  /// No plan or grasp.quality queued or running and no reload running.
  bool idle() const;
  const PlanningCatalog& catalog() const { return *catalog_; }
  int workers() const { return pool_.threads(); }

 private:
  /// A method's answer: a result, or an error; `note` goes to the log.
  struct Outcome {
    nlohmann::json result;
    std::optional<RpcError> error;
    std::string note;
  };
  using Finish = std::function<void(Outcome)>;
  using Handler = void (MethodDispatcher::*)(const Call&, const Caller&, const Finish&);

  /// Who a plan counts for (max_plans_per_client, the pool's fair share):
  /// the connection's token, or the connection on a server without tokens.
  static std::string clientOf(const Caller& caller);
  /// Throws unless the caller's role may call `method` (with tokens).
  void checkAccess(const std::string& method, const Caller& caller) const;
  void auth(const Call& call, const Caller& caller, const Finish& finish);
  void info(const Call& call, const Caller& caller, const Finish& finish);
  void objects(const Call& call, const Caller& caller, const Finish& finish);
  void scenes(const Call& call, const Caller& caller, const Finish& finish);
  void quality(const Call& call, const Caller& caller, const Finish& finish);
  void plan(const Call& call, const Caller& caller, const Finish& finish);
  void cancel(const Call& call, const Caller& caller, const Finish& finish);
  void shutdown(const Call& call, const Caller& caller, const Finish& finish);
  void reload(const Call& call, const Caller& caller, const Finish& finish);

  /// "error <code> <message>", as logged.
  static std::string describe(const RpcError& error);
  /// What server.info reports that changes only with the catalog.
  nlohmann::json staticInfo() const;
  static Outcome runPlan(const planner::PlanningWorld& world, const planner::PlanRequest& request,
                         const std::atomic<bool>& cancel, const PlanExtras& extras);
  static Outcome runQuality(const PlanningCatalog& catalog, const nlohmann::json& params,
                            const std::atomic<bool>& cancel);

  ServerOptions options_;
  PlanLimits limits_;
  std::shared_ptr<const PlanningCatalog> catalog_;
  std::shared_ptr<const TokenTable> tokens_;
  AuthThrottle throttle_;
  PostToIo post_;
  PostAfter post_after_;
  std::function<void()> on_shutdown_;
  RequestLog log_;
  WorkerPool pool_;          // plans
  WorkerPool quality_pool_;  // grasp.quality: one thread, queue as long as the plans'
  std::map<std::string, Handler> methods_;
  std::map<std::string, std::size_t> plans_of_client_;  // queued or running, by clientOf
  bool stopping_ = false;
  bool reloading_ = false;
  std::thread reload_thread_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::uint64_t calls_ = 0;
  nlohmann::json info_;  // staticInfo() of the current catalog, made on first use
  std::function<ConnectionLoad()> connection_load_;
};

}  // namespace hfts::service
