#include "core/scene/detail/ma_lexer.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace pushpin::scene::detail {

namespace {

enum CharClass : unsigned char {
    kWord = 0,   // may be part of a bare word
    kSpace,      // blank, tab, CR, FF, VT
    kNewline,    // '\n'
    kPunct,      // ; ( ) { } ,
    kQuote,      // "
    kBad,        // NUL and other control characters
};

constexpr std::array<unsigned char, 256> makeClasses() {
    std::array<unsigned char, 256> c{};
    for (int i = 0; i < 256; ++i) c[i] = kWord;
    for (int i = 0; i < 0x20; ++i) c[i] = kBad;
    c[0x7f] = kBad;
    c[' '] = c['\t'] = c['\r'] = c['\f'] = c['\v'] = kSpace;
    c['\n'] = kNewline;
    c[';'] = c['('] = c[')'] = c['{'] = c['}'] = c[','] = kPunct;
    c['"'] = kQuote;
    return c;
}
constexpr std::array<unsigned char, 256> kClasses = makeClasses();

inline unsigned char classOf(char c) { return kClasses[static_cast<unsigned char>(c)]; }

}  // namespace

bool MaToken::isFlag() const {
    if (kind != MaTokenKind::Word || text.size() < 2 || text[0] != '-') return false;
    const char c = text[1];
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'))) return false;
    // `-inf`, `-nan`, `-infinity` are (invalid) numbers rather than flags.
    if (c != 'i' && c != 'n' && c != 'I' && c != 'N') return true;
    const std::string_view t = text;  // compared by length first
    return t != "-inf" && t != "-nan" && t != "-infinity" && t != "-INF" && t != "-NAN";
}

MaLexer::MaLexer(std::istream& in, size_t bufferBytes) : m_in(&in), m_buffer(bufferBytes < 16 ? 16 : bufferBytes) {
    m_data = m_cur = m_end = m_buffer.data();
    refill();
    // A UTF-8 byte-order mark is not part of the text.
    if (m_end - m_cur >= 3 && static_cast<unsigned char>(m_cur[0]) == 0xEF &&
        static_cast<unsigned char>(m_cur[1]) == 0xBB && static_cast<unsigned char>(m_cur[2]) == 0xBF) {
        m_cur += 3;
        m_lineStart = 3;
    }
    checkHeader();
}

void MaLexer::checkHeader() {
    static constexpr std::string_view kHeader = "//Maya ASCII";
    m_mayaHeader = size_t(m_end - m_cur) >= kHeader.size() && std::string_view(m_cur, kHeader.size()) == kHeader;
}

MaLexer::MaLexer(std::string_view text) : m_eof(true) {
    m_data = m_cur = text.data();
    m_end = text.data() + text.size();
    if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF &&
        static_cast<unsigned char>(text[1]) == 0xBB && static_cast<unsigned char>(text[2]) == 0xBF) {
        m_cur += 3;
        m_lineStart = 3;
    }
    checkHeader();
}

bool MaLexer::refill() {
    if (m_cur < m_end) return true;
    if (m_eof || m_in == nullptr) {
        m_eof = true;
        return false;
    }
    m_base += uint64_t(m_end - m_data);
    m_in->read(m_buffer.data(), std::streamsize(m_buffer.size()));
    const auto got = static_cast<size_t>(m_in->gcount());
    m_data = m_cur = m_buffer.data();
    m_end = m_data + got;
    if (got == 0) {
        m_eof = true;
        return false;
    }
    return true;
}

void MaLexer::fail(uint32_t line, uint32_t column, std::string message) const {
    throw MaLexError{line, column, std::move(message)};
}

void MaLexer::failBadByte(unsigned char c) const {
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", c);
    fail(m_line, column(), std::string("invalid character ") + hex + " (binary data in a text file?)");
}

void MaLexer::skipBufferedWhitespace() {
    while (m_cur < m_end) {
        const unsigned char cls = classOf(*m_cur);
        if (cls == kSpace) {
            ++m_cur;
        } else if (cls == kNewline) {
            ++m_cur;
            ++m_line;
            m_lineStart = offset();
        } else {
            return;
        }
    }
}

void MaLexer::skipBlanks() {
    // The common case between the numbers of a list: spaces and tabs, maybe a newline, in the buffer.
    skipBufferedWhitespace();
    if (m_cur < m_end && *m_cur != '/') return;
    skipSpaceAndComments();  // a comment, or the end of the buffer
}

void MaLexer::skipSpaceAndComments() {
    for (;;) {
        skipBufferedWhitespace();
        if (m_cur == m_end) {
            if (!refill()) return;
            continue;
        }
        if (*m_cur != '/') return;
        // A comment starts only with "//" or "/*"; a lone '/' begins a word.
        const uint32_t line = m_line, col = column();
        ++m_cur;
        const int second = peekChar();
        if (second == '/') {
            // Line comment: skip to the newline (left for the whitespace loop to count), keeping its
            // first bytes for endsWithEndComment().
            ++m_cur;
            m_lastComment.clear();
            m_lastIsLineComment = true;
            for (;;) {
                const char* start = m_cur;
                while (m_cur < m_end && *m_cur != '\n') ++m_cur;
                for (const char* c = start; c < m_cur && m_lastComment.size() < kCommentKeep; ++c)
                    if (!m_lastComment.empty() || (*c != ' ' && *c != '\t')) m_lastComment.push_back(*c);
                if (m_cur < m_end || !refill()) break;
            }
        } else if (second == '*') {
            ++m_cur;
            m_lastIsLineComment = false;
            bool star = false;
            for (;;) {
                const int c = peekChar();
                if (c < 0) fail(line, col, "unterminated comment");
                ++m_cur;
                if (c == '\n') {
                    ++m_line;
                    m_lineStart = offset();
                }
                if (star && c == '/') break;
                star = c == '*';
            }
        } else {
            // Not a comment: step back onto the '/'. The previous byte is still in the buffer unless a
            // refill just happened, in which case the word starts with '/' that was consumed.
            if (m_cur > m_data) {
                --m_cur;
                return;
            }
            m_pendingSlash = true;
            m_pendingLine = line;
            m_pendingColumn = col;
            return;
        }
    }
}

void MaLexer::readWord(MaToken& token) {
    token.kind = MaTokenKind::Word;
    for (;;) {
        const char* start = m_cur;
        while (m_cur < m_end && classOf(*m_cur) == kWord) ++m_cur;
        token.text.append(start, size_t(m_cur - start));
        if (m_cur < m_end) {
            if (classOf(*m_cur) == kBad) failBadByte(static_cast<unsigned char>(*m_cur));
            return;
        }
        if (!refill()) return;
    }
}

void MaLexer::readString(MaToken& token) {
    token.kind = MaTokenKind::String;
    ++m_cur;  // opening quote
    for (;;) {
        const char* start = m_cur;
        while (m_cur < m_end) {
            const char c = *m_cur;
            const unsigned char cls = classOf(c);
            if (c == '"' || c == '\\' || cls == kNewline || cls == kBad) break;
            ++m_cur;
        }
        token.text.append(start, size_t(m_cur - start));
        if (m_cur == m_end) {
            if (!refill()) fail(token.line, token.column, "unterminated string (end of file inside a string)");
            continue;
        }
        const char c = *m_cur;
        if (c == '"') {
            ++m_cur;
            return;
        }
        if (c == '\n') fail(token.line, token.column, "unterminated string (end of line inside a string)");
        if (c != '\\') failBadByte(static_cast<unsigned char>(c));
        ++m_cur;
        const int e = peekChar();
        if (e < 0) fail(token.line, token.column, "unterminated string (end of file inside a string)");
        ++m_cur;
        switch (e) {
            case 'n': token.text.push_back('\n'); break;
            case 't': token.text.push_back('\t'); break;
            case 'r': token.text.push_back('\r'); break;
            case '\n':  // a backslash-newline continues the string on the next line
                ++m_line;
                m_lineStart = offset();
                break;
            default:
                if (classOf(char(e)) == kBad) failBadByte(static_cast<unsigned char>(e));
                token.text.push_back(char(e));  // \" \\ and any other escaped character
        }
    }
}

void MaLexer::next(MaToken& token) {
    token.text.clear();
    if (m_pendingSlash) {
        // A word that began with '/' just before a buffer boundary.
        m_pendingSlash = false;
        token.line = m_pendingLine;
        token.column = m_pendingColumn;
        token.text.push_back('/');
        if (m_cur < m_end || refill()) {
            if (classOf(*m_cur) == kWord) {
                readWord(token);
                return;
            }
        }
        token.kind = MaTokenKind::Word;
        return;
    }
    skipSpaceAndComments();
    if (m_pendingSlash) {
        next(token);
        return;
    }
    token.line = m_line;
    token.column = column();
    if (m_cur == m_end && !refill()) {
        token.kind = MaTokenKind::End;
        return;
    }
    m_lastIsLineComment = false;
    const char c = *m_cur;
    switch (classOf(c)) {
        case kWord: readWord(token); return;
        case kQuote: readString(token); return;
        case kPunct:
            ++m_cur;
            token.text.push_back(c);
            switch (c) {
                case ';': token.kind = MaTokenKind::Semicolon; break;
                case '(': token.kind = MaTokenKind::LParen; break;
                case ')': token.kind = MaTokenKind::RParen; break;
                case '{': token.kind = MaTokenKind::LBrace; break;
                case '}': token.kind = MaTokenKind::RBrace; break;
                default: token.kind = MaTokenKind::Comma; break;
            }
            return;
        default: failBadByte(static_cast<unsigned char>(c));
    }
}

bool MaLexer::nextPlainNumber(double& value) {
    if (m_pendingSlash) return false;
    skipBlanks();
    if (m_pendingSlash || m_cur >= m_end) return false;
    const char first = *m_cur;
    if (!((first >= '0' && first <= '9') || first == '-' || first == '.')) return false;
    // One pass: the number ends where from_chars stops, which must be the end of the word. A
    // number that runs to the end of the buffer is left to the token path (it may go on).
    const auto [ptr, ec] = std::from_chars(m_cur, m_end, value);
    if (ec != std::errc() || ptr == m_cur) return false;
    if (ptr == m_end ? !m_eof : classOf(*ptr) == kWord) return false;
    if (!std::isfinite(value)) return false;
    m_cur = ptr;
    m_lastIsLineComment = false;
    return true;
}

bool MaLexer::nextPlainInteger(int64_t& value) {
    if (m_pendingSlash) return false;
    skipBlanks();
    if (m_pendingSlash || m_cur >= m_end) return false;
    // One pass over an optional '-' and at most 18 digits (which cannot overflow); anything
    // longer, or a word that goes on past the digits, is left to the token path.
    const char* q = m_cur;
    const bool negative = *q == '-';
    if (negative) ++q;
    const char* digits = q;
    uint64_t v = 0;
    while (q < m_end && q - digits < 19 && *q >= '0' && *q <= '9') v = v * 10 + uint64_t(*q++ - '0');
    if (q == digits || q - digits > 18) return false;
    if (q == m_end ? !m_eof : classOf(*q) == kWord) return false;
    value = negative ? -int64_t(v) : int64_t(v);
    m_cur = q;
    m_lastIsLineComment = false;
    return true;
}

}  // namespace pushpin::scene::detail
