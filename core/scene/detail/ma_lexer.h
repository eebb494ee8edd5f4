// core/scene/detail/ma_lexer.h: splits Maya ASCII text into tokens (words, quoted strings,
// punctuation), streaming through a fixed-size buffer so that a file is never held in memory whole.
// Text already in memory is tokenised in place, without a copy.
// Thread safety: one lexer per reading thread. Memory: the buffer (1 MiB by default) plus the
// current token's text.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::scene::detail {

enum class MaTokenKind : unsigned char {
    Word,       // bare word: command, flag, number, `yes`, `:node`, `Index_Data` …
    String,     // double-quoted string; `text` holds the decoded characters
    Semicolon,  // `;` ends a command
    LParen,     // `(`
    RParen,     // `)`
    LBrace,     // `{`
    RBrace,     // `}`
    Comma,      // `,`
    End,        // end of input
};

struct MaToken {
    MaTokenKind kind = MaTokenKind::End;
    std::string text;  // reused between tokens, so reading a token rarely allocates
    uint32_t line = 0;
    uint32_t column = 0;

    bool isWord(std::string_view w) const { return kind == MaTokenKind::Word && text == w; }
    // A flag is a word starting with '-' followed by a letter (`-type`), unlike `-0.5` or `-inf`.
    bool isFlag() const;
};

// Where the lexer stopped, for errors raised by the lexer itself.
struct MaLexError {
    uint32_t line = 0;
    uint32_t column = 0;
    std::string message;
};

class MaLexer {
public:
    static constexpr size_t kDefaultBufferBytes = size_t(1) << 20;

    // Streams from `in` through a buffer of `bufferBytes`. `in` must outlive the lexer.
    explicit MaLexer(std::istream& in, size_t bufferBytes = kDefaultBufferBytes);
    // Tokenises `text` in place; `text` must outlive the lexer.
    explicit MaLexer(std::string_view text);

    // Reads the next token into `token`. Comments (`//…`, `/*…*/`) and whitespace are skipped.
    // Throws MaLexError on an unterminated string or a byte that cannot occur in a text file
    // (NUL and other control characters).
    void next(MaToken& token);
    // The fast path of long number lists: when the next token is a plain finite number (decimal,
    // no unit suffix, no leading '+') lying wholly in the buffer, reads it into `value` and returns
    // true; otherwise returns false having consumed at most whitespace and comments, and next()
    // reads the token as usual. The integer form takes a plain `-`? and up to 18 digits.
    bool nextPlainNumber(double& value);
    bool nextPlainInteger(int64_t& value);

    // Position just past the last character consumed (1-based line and column).
    uint32_t line() const { return m_line; }
    uint32_t column() const { return uint32_t(offset() - m_lineStart + 1); }
    // Bytes consumed so far.
    uint64_t offset() const { return m_base + uint64_t(m_cur - m_data); }

    // Whether the input starts with the header Maya writes ("//Maya ASCII"), after any BOM.
    bool hasMayaHeader() const { return m_mayaHeader; }
    // At end of input: whether the last thing in it is the comment Maya writes last
    // ("// End of scene.ma"), with nothing but whitespace after it.
    bool endsWithEndComment() const { return m_lastIsLineComment && m_lastComment.rfind("End of", 0) == 0; }

private:
    bool refill();  // false at end of input; invalidates pointers into the old buffer
    int peekChar() {
        if (m_cur == m_end && !refill()) return -1;
        return static_cast<unsigned char>(*m_cur);
    }
    void skipSpaceAndComments();
    void skipBlanks();  // skipSpaceAndComments() with the plain case inline
    void skipBufferedWhitespace();  // spaces, tabs and newlines up to the end of the buffer
    void checkHeader();
    void readWord(MaToken& token);
    void readString(MaToken& token);
    [[noreturn]] void fail(uint32_t line, uint32_t column, std::string message) const;
    [[noreturn]] void failBadByte(unsigned char c) const;

    std::istream* m_in = nullptr;
    std::vector<char> m_buffer;
    const char* m_data = nullptr;  // start of the current buffer contents
    const char* m_cur = nullptr;
    const char* m_end = nullptr;
    uint64_t m_base = 0;       // offset of m_data in the input
    uint64_t m_lineStart = 0;  // offset of the first byte of the current line
    uint32_t m_line = 1;
    bool m_eof = false;
    bool m_mayaHeader = false;
    // The start of the last `//` comment (leading spaces dropped, at most kCommentKeep bytes) and
    // whether nothing but whitespace followed it so far.
    static constexpr size_t kCommentKeep = 16;
    std::string m_lastComment;
    bool m_lastIsLineComment = false;
    // A '/' that was not a comment, seen just before a buffer refill: the next word starts with it.
    bool m_pendingSlash = false;
    uint32_t m_pendingLine = 0, m_pendingColumn = 0;
};

}  // namespace pushpin::scene::detail
