// core/util/json_writer.h: a small streaming JSON writer for reports (--info, --stats, botinfo).
// Produces valid JSON whatever it is given: strings are escaped, non-finite numbers become null.
// Not thread-safe; one writer per document.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::util {

class JsonWriter {
public:
    explicit JsonWriter(int indent = 2) : m_indent(indent) {}

    JsonWriter& beginObject() { return open('{'); }
    JsonWriter& endObject() { return close('}'); }
    JsonWriter& beginArray() { return open('['); }
    JsonWriter& endArray() { return close(']'); }
    // The key of the next value inside an object.
    JsonWriter& key(std::string_view k) {
        separate();
        writeString(k);
        m_out += m_indent > 0 ? ": " : ":";
        m_afterKey = true;
        return *this;
    }
    JsonWriter& value(std::string_view s) {
        separate();
        writeString(s);
        return *this;
    }
    JsonWriter& value(const char* s) { return value(std::string_view(s)); }
    JsonWriter& value(const std::string& s) { return value(std::string_view(s)); }
    JsonWriter& value(bool b) {
        separate();
        m_out += b ? "true" : "false";
        return *this;
    }
    JsonWriter& value(double d) {
        separate();
        if (!std::isfinite(d)) {
            m_out += "null";
        } else if (d == std::floor(d) && std::fabs(d) < 1e15) {
            m_out += std::to_string(int64_t(d));
        } else {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.9g", d);
            m_out += buf;
        }
        return *this;
    }
    JsonWriter& value(int v) { return value(int64_t(v)); }
    JsonWriter& value(int64_t v) {
        separate();
        m_out += std::to_string(v);
        return *this;
    }
    JsonWriter& value(uint64_t v) {
        separate();
        m_out += std::to_string(v);
        return *this;
    }
    JsonWriter& null() {
        separate();
        m_out += "null";
        return *this;
    }
    template <typename T>
    JsonWriter& field(std::string_view k, const T& v) {
        key(k);
        return value(v);
    }

    const std::string& str() const { return m_out; }

private:
    JsonWriter& open(char c) {
        separate();
        m_out += c;
        m_first.push_back(true);
        return *this;
    }
    JsonWriter& close(char c) {
        bool empty = m_first.empty() || m_first.back();
        if (!m_first.empty()) m_first.pop_back();
        if (!empty) newline();
        m_out += c;
        return *this;
    }
    void separate() {
        if (m_afterKey) {
            m_afterKey = false;
            return;
        }
        if (m_first.empty()) return;
        if (!m_first.back()) m_out += ',';
        m_first.back() = false;
        newline();
    }
    void newline() {
        if (m_indent <= 0) return;
        m_out += '\n';
        m_out.append(m_first.size() * size_t(m_indent), ' ');
    }
    // Length of a valid UTF-8 sequence starting at s[i], or 0 if the bytes there are not one.
    static size_t utf8Length(std::string_view s, size_t i) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        size_t n = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
        if (n == 0 || i + n > s.size()) return 0;
        for (size_t k = 1; k < n; ++k)
            if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
        return n;
    }
    void writeString(std::string_view s) {
        m_out += '"';
        for (size_t i = 0; i < s.size(); ++i) {
            unsigned char c = static_cast<unsigned char>(s[i]);
            if (c >= 0x80) {
                // Valid UTF-8 passes through. Any other byte (names in 8-bit legacy encodings,
                // Latin-1 in older Maya files) is escaped as the Latin-1 character it would be,
                // so the document stays valid and the byte can be told from any other.
                size_t n = utf8Length(s, i);
                if (n == 0) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    m_out += buf;
                } else {
                    m_out.append(s.substr(i, n));
                    i += n - 1;
                }
                continue;
            }
            switch (c) {
                case '"': m_out += "\\\""; break;
                case '\\': m_out += "\\\\"; break;
                case '\n': m_out += "\\n"; break;
                case '\r': m_out += "\\r"; break;
                case '\t': m_out += "\\t"; break;
                default:
                    if (c < 0x20 || c == 0x7F) {
                        char buf[8];
                        std::snprintf(buf, sizeof buf, "\\u%04x", c);
                        m_out += buf;
                    } else {
                        m_out += char(c);
                    }
            }
        }
        m_out += '"';
    }

    int m_indent;
    std::string m_out;
    std::vector<bool> m_first;  // per open container: no element written yet
    bool m_afterKey = false;
};

}  // namespace pushpin::util
