// core/scene/detail/ma_number.h: number and boolean words of Maya ASCII values: `0.5`, `-1e+020`,
// `yes`/`off`, and numbers with a unit suffix (`5m`, `4inch`, `90deg`, `6ntsc`).
// Pure functions; thread-safe.
#pragma once

#include "core/scene/units.h"

#include <cstdint>
#include <string_view>

namespace pushpin::scene::detail {

enum class MaNumberStatus : unsigned char {
    Ok,
    NotANumber,   // not a number, boolean or number with a known unit suffix
    NotFinite,    // nan / inf
    OutOfRange,   // magnitude beyond a double (1e999)
};

struct MaNumber {
    MaNumberStatus status = MaNumberStatus::NotANumber;
    double value = 0.0;
    bool hasUnit = false;  // a unit suffix was given: `value` is already in internal units
};

// Parses a word as a number. `yes/no/on/off/true/false` are 1 and 0. A unit suffix converts to
// internal units (cm, radians, frames of `units`' time unit); `kind` picks the meaning of the
// ambiguous suffixes `min`/`sec` (angle for Angle attributes, time otherwise).
// Underflow (1e-999) reads as zero.
MaNumber parseMaNumber(std::string_view word, UnitKind kind, const Units& units);

// Parses a whole word as a decimal integer (optional sign, digits only). False if it is not one or
// does not fit in int64.
bool parseMaInteger(std::string_view word, int64_t& out);

// `yes/no/on/off/true/false/1/0` → true/false. False if the word is not a boolean.
bool parseMaBool(std::string_view word, bool& out);

}  // namespace pushpin::scene::detail
