#include "core/scene/units.h"

#include <charconv>
#include <numbers>
#include <string>

namespace pushpin::scene {

std::optional<double> linearUnitInCm(std::string_view t) {
    if (t == "mm" || t == "millimeter" || t == "millimetre") return 0.1;
    if (t == "cm" || t == "centimeter" || t == "centimetre") return 1.0;
    if (t == "m" || t == "meter" || t == "metre") return 100.0;
    if (t == "km" || t == "kilometer" || t == "kilometre") return 100000.0;
    if (t == "in" || t == "inch") return 2.54;
    if (t == "ft" || t == "foot") return 30.48;
    if (t == "yd" || t == "yard") return 91.44;
    if (t == "mi" || t == "mile") return 160934.4;
    return std::nullopt;
}

std::optional<double> angleUnitInRadians(std::string_view t) {
    constexpr double pi = std::numbers::pi;
    if (t == "deg" || t == "degree") return pi / 180.0;
    if (t == "rad" || t == "radian") return 1.0;
    if (t == "min") return pi / 10800.0;
    if (t == "sec") return pi / 648000.0;
    return std::nullopt;
}

std::optional<double> timeUnitFps(std::string_view t) {
    if (t == "game") return 15.0;
    if (t == "film") return 24.0;
    if (t == "pal") return 25.0;
    if (t == "ntsc") return 30.0;
    if (t == "show") return 48.0;
    if (t == "palf") return 50.0;
    if (t == "ntscf") return 60.0;
    if (t == "millisec" || t == "millisecond") return 1000.0;
    if (t == "sec" || t == "second") return 1.0;
    if (t == "min" || t == "minute") return 1.0 / 60.0;
    if (t == "hour") return 1.0 / 3600.0;
    // "<n>fps", e.g. 23.976fps, 120fps (newer Maya versions).
    if (t.size() > 3 && t.substr(t.size() - 3) == "fps") {
        double fps = 0.0;
        std::string_view num = t.substr(0, t.size() - 3);
        auto [ptr, ec] = std::from_chars(num.data(), num.data() + num.size(), fps);
        if (ec == std::errc() && ptr == num.data() + num.size() && fps > 0.0) return fps;
    }
    return std::nullopt;
}

double toInternal(UnitKind kind, const Units& units) {
    switch (kind) {
        case UnitKind::Distance: return units.cmPerLinearUnit;
        case UnitKind::Angle: return units.radiansPerAngleUnit;
        case UnitKind::Time:  // times stay in frames of the scene's time unit
        case UnitKind::None: break;
    }
    return 1.0;
}

}  // namespace pushpin::scene
