// core/util/format.h: numbers and user text in messages. formatNumber gives the shortest text that
// reads back as the same double (up to `precision` significant digits), "nan"/"inf" as the stream
// writes them; excerpt bounds how much of a token from the input a message repeats. Thread-safe.
#pragma once

#include <cstddef>
#include <sstream>
#include <string>
#include <string_view>

namespace pushpin::util {

inline std::string formatNumber(double value, int precision = 17) {
    std::ostringstream out;
    out.precision(precision);
    out << value;
    return out.str();
}

// Most characters of one token a diagnostic quotes: a 50 MB name still makes a one-line message.
constexpr size_t kMaxQuotedChars = 200;

// `text` itself when it has at most `maxChars` bytes, else its first `maxChars` bytes (never
// cutting a UTF-8 sequence in two) followed by "... (N bytes)".
inline std::string excerpt(std::string_view text, size_t maxChars = kMaxQuotedChars) {
    if (text.size() <= maxChars) return std::string(text);
    size_t cut = maxChars;
    // Back up over continuation bytes (10xxxxxx) so the cut falls between characters.
    while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
    return std::string(text.substr(0, cut)) + "... (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace pushpin::util
