#include "core/scene/detail/ma_number.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace pushpin::scene::detail {

namespace {

// Converts `value` given in the unit `suffix` to internal units; false if `suffix` is no unit.
bool applyUnitSuffix(double& value, std::string_view suffix, UnitKind kind, const Units& units) {
    auto asLinear = [&] {
        if (auto cm = linearUnitInCm(suffix)) return value *= *cm, true;
        return false;
    };
    auto asAngle = [&] {
        if (auto rad = angleUnitInRadians(suffix)) return value *= *rad, true;
        return false;
    };
    auto asTime = [&] {
        if (auto fps = timeUnitFps(suffix)) return value = value / *fps * units.framesPerSecond, true;
        return false;
    };
    switch (kind) {
        case UnitKind::Distance: return asLinear();
        case UnitKind::Angle: return asAngle();
        case UnitKind::Time: return asTime();
        case UnitKind::None: break;
    }
    return asLinear() || asTime() || asAngle();
}

}  // namespace

bool parseMaBool(std::string_view w, bool& out) {
    if (w == "yes" || w == "on" || w == "true" || w == "1") return out = true, true;
    if (w == "no" || w == "off" || w == "false" || w == "0") return out = false, true;
    return false;
}

bool parseMaInteger(std::string_view w, int64_t& out) {
    const char* b = w.data();
    const char* e = b + w.size();
    if (b != e && *b == '+') ++b;
    if (b == e) return false;
    auto [ptr, ec] = std::from_chars(b, e, out);
    return ec == std::errc() && ptr == e;
}

MaNumber parseMaNumber(std::string_view w, UnitKind kind, const Units& units) {
    MaNumber r;
    if (w.empty()) return r;
    const char first = w.front();
    // Booleans are the only words that start with a letter and still are numbers.
    if ((first >= 'a' && first <= 'z') || (first >= 'A' && first <= 'Z')) {
        bool b = false;
        if (parseMaBool(w, b)) {
            r.status = MaNumberStatus::Ok;
            r.value = b ? 1.0 : 0.0;
            return r;
        }
        if (w == "nan" || w == "inf" || w == "infinity" || w == "NaN" || w == "INF" || w == "NAN")
            r.status = MaNumberStatus::NotFinite;
        return r;
    }
    const char* b = w.data();
    const char* e = b + w.size();
    if (*b == '+') ++b;
    if (b == e) return r;
    auto [ptr, ec] = std::from_chars(b, e, r.value);
    if (ec == std::errc::invalid_argument) return r;
    if (ec == std::errc::result_out_of_range) {
        // from_chars reports both overflow and underflow; an underflow (negative exponent) is zero.
        bool negativeExponent = false;
        for (const char* p = b; p + 1 < ptr; ++p)
            if ((*p == 'e' || *p == 'E') && p[1] == '-') negativeExponent = true;
        if (!negativeExponent) {
            r.status = MaNumberStatus::OutOfRange;
            return r;
        }
        r.value = (*b == '-') ? -0.0 : 0.0;
    }
    if (!std::isfinite(r.value)) {
        r.status = MaNumberStatus::NotFinite;
        return r;
    }
    if (ptr != e) {
        if (!applyUnitSuffix(r.value, std::string_view(ptr, size_t(e - ptr)), kind, units)) return r;
        if (!std::isfinite(r.value)) {
            r.status = MaNumberStatus::OutOfRange;
            return r;
        }
        r.hasUnit = true;
    }
    r.status = MaNumberStatus::Ok;
    return r;
}

}  // namespace pushpin::scene::detail
