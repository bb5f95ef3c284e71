#pragma once
// UTF-8 checks for text that comes from outside (request paths and queries, command-line words)
// and goes into JSON or a log line: nlohmann::json refuses to dump a string that is not UTF-8.

#include <string>
#include <string_view>

namespace artemis::viewer {

// Whether `text` is well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, nothing past
// U+10FFFF).
bool isValidUtf8(std::string_view text);

// `text` with each byte that is not part of a well-formed sequence replaced by U+FFFD, as
// nlohmann::json's error_handler_t::replace does; valid text comes back unchanged.
std::string toValidUtf8(std::string_view text);

}  // namespace artemis::viewer
