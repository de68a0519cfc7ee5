#pragma once
// One log line per request.

#include <chrono>
#include <iosfwd>
#include <string>

namespace hfts::service {

/// Writes "<UTC time> <peer> id=<id> <method> <duration> <outcome>" lines,
/// e.g. "2026-11-21T10:31:02.123Z 127.0.0.1:50432 id=7 plan 0.412s ok success".
/// Control characters in the fields become spaces, so a line stays a line.
/// A null stream writes nothing. Thread-safe.
class RequestLog {
 public:
  explicit RequestLog(std::ostream* out) : out_(out) {}

  void write(const std::string& peer, const std::string& id, const std::string& method,
             std::chrono::steady_clock::duration duration, const std::string& outcome) const;
  /// A free-form server event ("listening on ...", "shutting down").
  void event(const std::string& text) const;
  /// Sends OMPL's console messages (process-wide) to this log as events,
  /// so that they too take one line each; with a null stream they are dropped.
  void captureOmplMessages() const;

 private:
  std::ostream* out_;
};

}  // namespace hfts::service
