#pragma once
// Who may call what (docs/security.md): the tokens of `hfts-server
// --auth-tokens FILE`, their roles, the methods each role may call, and the
// throttle on failed authentications.

#include <array>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hfts::service {

/// What a token lets a connection do. kPlan: plan, grasp.quality, cancel,
/// server.info and the lists; kAdmin: all of that, and reload and shutdown.
enum class Role { kPlan, kAdmin };

const char* toString(Role role);

/// The least role that may call `method`; nullopt for `auth` (which any
/// connection may call) and for names that are no method.
std::optional<Role> requiredRole(const std::string& method);

/// Whether `role` may call what needs `required`.
inline bool allows(Role role, Role required) {
  return role == Role::kAdmin || required == Role::kPlan;
}

/// SHA-256 of a token: the table keeps digests only, never the tokens.
using TokenDigest = std::array<unsigned char, 32>;
TokenDigest digestOf(const std::string& token);

/// One line of a token file.
struct TokenEntry {
  TokenDigest digest{};
  Role role = Role::kPlan;
  std::string name;  ///< for the log: the line's third word, else "line N"
};

/// The tokens a server accepts. A token file has one token per line:
///
///     ROLE TOKEN [NAME]
///
/// ROLE is `plan` or `admin`; TOKEN 16 to 1024 printable ASCII characters
/// without spaces (e.g. `openssl rand -hex 32`); NAME (optional) names the
/// client in the log, which never shows a token. Empty lines and lines
/// starting with `#` are skipped.
class TokenTable {
 public:
  /// Reads `file`. Throws std::runtime_error naming the file (and the line)
  /// when it cannot be read, when every user may read or write it (the
  /// message says `chmod 600`), for a malformed line, a repeated token, or
  /// a file without any token.
  static TokenTable load(const std::filesystem::path& file);
  /// The tokens of a file's `text`; `source` names it in errors.
  static TokenTable parse(const std::string& text, const std::string& source);

  /// The entry of `token`, or null. Takes the same time whichever entry
  /// matches, or none: every entry is compared, in constant time, with the
  /// token's digest.
  const TokenEntry* find(const std::string& token) const { return find(digestOf(token)); }
  const TokenEntry* find(const TokenDigest& digest) const;
  std::size_t size() const { return entries_.size(); }

 private:
  std::vector<TokenEntry> entries_;
};

/// Failed authentications per peer address: after `max_failures` within
/// `window`, the address is refused without a check for `block`. Keeps at
/// most kMaxAddresses addresses (the oldest forgotten first). Used only on
/// the server's I/O thread.
class AuthThrottle {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::size_t kMaxAddresses = 4096;

  explicit AuthThrottle(int maxFailures = 5, std::chrono::seconds window = std::chrono::seconds(60),
                        std::chrono::seconds block = std::chrono::seconds(60))
      : max_failures_(maxFailures), window_(window), block_(block) {}

  /// How long `address` must still wait before it may try again (zero: it
  /// may try now).
  Clock::duration blockedFor(const std::string& address, Clock::time_point now) const;
  /// Counts a failure of `address`.
  void failed(const std::string& address, Clock::time_point now);

 private:
  struct Record {
    int failures = 0;
    Clock::time_point first{};          // of the failures counted
    Clock::time_point blocked_until{};  // zero: not blocked
  };
  int max_failures_;
  Clock::duration window_, block_;
  std::map<std::string, Record> records_;
};

}  // namespace hfts::service
