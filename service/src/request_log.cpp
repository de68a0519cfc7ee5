#include "request_log.h"

#include <ompl/util/Console.h>

#include <atomic>
#include <ctime>
#include <iomanip>
#include <mutex>
#include <ostream>
#include <sstream>

namespace hfts::service {
namespace {

std::mutex& logMutex() {
  static std::mutex m;
  return m;
}

std::string utcNow() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()) % 1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  std::ostringstream s;
  s << std::put_time(&utc, "%Y-%m-%dT%H:%M:%S") << '.' << std::setw(3) << std::setfill('0')
    << ms.count() << 'Z';
  return s.str();
}

/// At most `limit` bytes, control characters as spaces.
std::string oneLine(std::string text, std::size_t limit = 200) {
  if (text.size() > limit) text = text.substr(0, limit) + "...";
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return text;
}

/// OMPL reports through one process-wide handler; it writes to the stream
/// of the last log that captured it.
class OmplToLog : public ompl::msg::OutputHandler {
 public:
  void log(const std::string& text, ompl::msg::LogLevel, const char*, int) override {
    RequestLog(out.load()).event("ompl: " + text);
  }
  std::atomic<std::ostream*> out{nullptr};
};

}  // namespace

void RequestLog::captureOmplMessages() const {
  static OmplToLog handler;
  handler.out = out_;
  ompl::msg::useOutputHandler(&handler);
}

void RequestLog::write(const std::string& peer, const std::string& id, const std::string& method,
                       std::chrono::steady_clock::duration duration,
                       const std::string& outcome) const {
  if (out_ == nullptr) return;
  std::ostringstream line;
  line << utcNow() << ' ' << peer << " id=" << oneLine(id) << ' ' << oneLine(method) << ' '
       << std::fixed << std::setprecision(6) << std::chrono::duration<double>(duration).count()
       << "s " << oneLine(outcome) << '\n';
  const std::lock_guard<std::mutex> lock(logMutex());
  *out_ << line.str() << std::flush;
}

void RequestLog::event(const std::string& text) const {
  if (out_ == nullptr) return;
  const std::string line = utcNow() + ' ' + oneLine(text) + '\n';
  const std::lock_guard<std::mutex> lock(logMutex());
  *out_ << line << std::flush;
}

}  // namespace hfts::service
