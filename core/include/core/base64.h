#pragma once
// Base64 (RFC 4648, with padding) for binary data inside JSON: the plan
// result's glTF.

#include <string>
#include <string_view>

namespace hfts::core {

std::string base64Encode(std::string_view bytes);

/// Throws InvalidArgument (field `what`) for a length that is not a
/// multiple of 4 or a character outside the alphabet and padding.
std::string base64Decode(std::string_view text, const std::string& what = "base64");

}  // namespace hfts::core
