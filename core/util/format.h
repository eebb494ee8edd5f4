// core/util/format.h: numbers in messages: the shortest text that reads back as the same double
// (up to `precision` significant digits), "nan"/"inf" as the stream writes them. Thread-safe.
#pragma once

#include <sstream>
#include <string>

namespace pushpin::util {

inline std::string formatNumber(double value, int precision = 17) {
    std::ostringstream out;
    out.precision(precision);
    out << value;
    return out.str();
}

}  // namespace pushpin::util
