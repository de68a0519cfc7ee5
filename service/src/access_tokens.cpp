#include "service/access_tokens.h"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hfts::service {

namespace {

constexpr std::size_t kMinTokenLength = 16;
constexpr std::size_t kMaxTokenLength = 1024;

bool printableWord(const std::string& word) {
  return std::all_of(word.begin(), word.end(), [](char c) { return c > ' ' && c < 127; });
}

std::string modeText(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

}  // namespace

const char* toString(Role role) {
  return role == Role::kAdmin ? "admin" : "plan";
}

std::optional<Role> requiredRole(const std::string& method) {
  static const std::map<std::string, Role> kRoles{
      {"server.info", Role::kPlan}, {"objects.list", Role::kPlan},  {"scenes.list", Role::kPlan},
      {"plan", Role::kPlan},        {"grasp.quality", Role::kPlan}, {"cancel", Role::kPlan},
      {"reload", Role::kAdmin},     {"shutdown", Role::kAdmin}};
  const auto found = kRoles.find(method);
  if (found == kRoles.end()) return std::nullopt;
  return found->second;
}

TokenDigest digestOf(const std::string& token) {
  TokenDigest digest{};
  unsigned int length = 0;
  if (EVP_Digest(token.data(), token.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1 ||
      length != digest.size())
    throw std::runtime_error("SHA-256 of a token failed (OpenSSL)");
  return digest;
}

TokenTable TokenTable::load(const std::filesystem::path& file) {
  struct stat status {};
  if (::stat(file.c_str(), &status) != 0)
    throw std::runtime_error("token file '" + file.string() + "' cannot be read");
  if (!S_ISREG(status.st_mode))
    throw std::runtime_error("token file '" + file.string() + "' is not a regular file");
  if ((status.st_mode & (S_IROTH | S_IWOTH)) != 0)
    throw std::runtime_error("token file '" + file.string() + "' may be read or written by every " +
                             "user (mode " + modeText(status.st_mode) + "): chmod 600 '" +
                             file.string() + "'");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("token file '" + file.string() + "' cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::runtime_error("token file '" + file.string() + "' cannot be read");
  return parse(text.str(), "token file '" + file.string() + "'");
}

TokenTable TokenTable::parse(const std::string& text, const std::string& source) {
  TokenTable table;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto fail = [&](const std::string& problem) {
      throw std::runtime_error(source + ", line " + std::to_string(number) + ": " + problem);
    };
    std::istringstream words(line);
    std::string role, token, name, extra;
    if (!(words >> role) || role.front() == '#') continue;
    if (!(words >> token)) fail("a token is missing after the role (ROLE TOKEN [NAME])");
    words >> name;
    if (words >> extra) fail("more than ROLE TOKEN [NAME]");
    TokenEntry entry;
    if (role == "plan")
      entry.role = Role::kPlan;
    else if (role == "admin")
      entry.role = Role::kAdmin;
    else
      fail("the role must be plan or admin, not '" + role + "'");
    if (token.size() < kMinTokenLength || token.size() > kMaxTokenLength)
      fail("a token must have " + std::to_string(kMinTokenLength) + " to " +
           std::to_string(kMaxTokenLength) + " characters (this one has " +
           std::to_string(token.size()) + ")");
    if (!printableWord(token) || !printableWord(name))
      fail("tokens and names are printable ASCII without spaces");
    entry.digest = digestOf(token);
    entry.name = name.empty() ? "line " + std::to_string(number) : name;
    if (table.find(entry.digest) != nullptr) fail("this token is already on an earlier line");
    table.entries_.push_back(std::move(entry));
  }
  if (table.entries_.empty()) throw std::runtime_error(source + " holds no token");
  return table;
}

const TokenEntry* TokenTable::find(const TokenDigest& digest) const {
  // Every entry is compared and the loop never leaves early, so the time
  // does not tell which entry (if any) matched.
  const TokenEntry* match = nullptr;
  for (const TokenEntry& entry : entries_) {
    const bool same = CRYPTO_memcmp(entry.digest.data(), digest.data(), digest.size()) == 0;
    match = same ? &entry : match;
  }
  return match;
}

AuthThrottle::Clock::duration AuthThrottle::blockedFor(const std::string& address,
                                                       Clock::time_point now) const {
  const auto found = records_.find(address);
  if (found == records_.end() || found->second.blocked_until <= now) return Clock::duration::zero();
  return found->second.blocked_until - now;
}

void AuthThrottle::failed(const std::string& address, Clock::time_point now) {
  if (records_.size() >= kMaxAddresses && records_.count(address) == 0) {
    // Forget the address whose count began longest ago.
    auto oldest = std::min_element(
        records_.begin(), records_.end(),
        [](const auto& a, const auto& b) { return a.second.first < b.second.first; });
    records_.erase(oldest);
  }
  Record& record = records_[address];
  if (record.failures == 0 || now - record.first > window_) {
    record.failures = 0;
    record.first = now;
  }
  if (++record.failures >= max_failures_) {
    record.blocked_until = now + block_;
    record.failures = 0;
  }
}

}  // namespace hfts::service
