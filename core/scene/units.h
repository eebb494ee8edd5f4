// core/scene/units.h: Maya's linear, angular and time units and their conversion to the internal
// units (centimetres, radians, frames of the scene's time unit). Pure functions; thread-safe.
#pragma once

#include <optional>
#include <string_view>

namespace pushpin::scene {

// What physical quantity an attribute value carries; decides how `currentUnit` scales it on load.
enum class UnitKind : unsigned char { None, Distance, Angle, Time };

// The units a .ma file was written in (`currentUnit -l -a -t`), as factors to internal units.
struct Units {
    double cmPerLinearUnit = 1.0;                      // centimetre is Maya's internal length
    double radiansPerAngleUnit = 0.017453292519943295;  // files default to degrees
    double framesPerSecond = 24.0;                     // "film"
};

// Centimetres in one `-l` unit token (mm, millimeter, cm, m, km, in, ft, yd, mi, …); nullopt if unknown.
std::optional<double> linearUnitInCm(std::string_view token);
// Radians in one `-a` unit token (deg, degree, rad, radian, min, sec); nullopt if unknown.
std::optional<double> angleUnitInRadians(std::string_view token);
// Frames per second of a `-t` token (game 15, film 24, pal 25, ntsc 30, show 48, palf 50, ntscf 60,
// "<n>fps", millisec 1000, sec 1, min 1/60, hour 1/3600); nullopt if unknown.
std::optional<double> timeUnitFps(std::string_view token);

// Scale factor that converts a value of `kind` written in `units` to internal units.
double toInternal(UnitKind kind, const Units& units);

}  // namespace pushpin::scene
