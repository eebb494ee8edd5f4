// core/scene/anim_curve.h: evaluation of a Maya animCurve (animCurveTL/TA/TU/TT/UL/UA/UU) from its
// keys, tangent types, explicit tangents and pre/post infinity. Pure: an AnimCurve is built once from
// plain key data (tangents are resolved at construction) and is immutable afterwards, so evaluate()
// may run on many threads at once. Memory: a few doubles per key.
//
// Units are the caller's: key times in frames (T* curves) or input units (U* curves), values and
// explicit tangent y in the value's internal unit, explicit tangent x in the same unit as key times.
#pragma once

#include <cstddef>
#include <vector>

namespace pushpin::scene {

// The integers Maya writes in `.tan`, `.kit` and `.kot` (the animCurve node's tangent enum; it differs
// from MFnAnimCurve::TangentType). Values seen in files: 1 fixed, 2 linear, 3 flat, 5 step, 9 spline,
// 10 clamped (Maya's default before 2017), 16 plateau, 17 step next, 18 auto (default since 2017).
enum class TangentType : int {
    Global = 0,  // use the curve's tangentType
    Fixed = 1,
    Linear = 2,
    Flat = 3,
    Step = 5,
    Slow = 6,  // obsolete in Maya; evaluated as Spline
    Fast = 7,  // obsolete in Maya; evaluated as Spline
    Spline = 9,
    Clamped = 10,
    Plateau = 16,
    StepNext = 17,
    Auto = 18,
    AutoMix = 27,     // evaluated as Auto
    AutoEase = 28,    // evaluated as Auto
    AutoCustom = 29,  // evaluated as Auto
};

// `preInfinity` / `postInfinity` (MFnAnimCurve::InfinityType uses the same integers).
enum class InfinityType : int { Constant = 0, Linear = 1, Cycle = 3, CycleRelative = 4, Oscillate = 5 };

// Converts a stored integer to the enum; unknown values become Global / Constant.
TangentType tangentTypeFromInt(int v);
InfinityType infinityTypeFromInt(int v);

struct AnimKey {
    double time = 0.0;   // ktv[i] first number
    double value = 0.0;  // ktv[i] second number
    TangentType inType = TangentType::Global;   // kit[i]
    TangentType outType = TangentType::Global;  // kot[i]
    // Explicit tangent vectors (kix/kiy, kox/koy). Non-weighted curves only use their direction;
    // weighted curves also use their length (the control point sits a third of the vector away).
    bool hasInTangent = false;
    double inX = 1.0, inY = 0.0;
    bool hasOutTangent = false;
    double outX = 1.0, outY = 0.0;
    bool breakdown = false;  // keyBreakdown: an editing hint, no effect on evaluation
};

struct AnimCurveData {
    std::vector<AnimKey> keys;  // any order; sorted by time (stable) on construction
    TangentType tangentType = TangentType::Clamped;  // `tan`, used by keys whose type is Global
    bool weightedTangents = false;                   // `wgt`
    InfinityType preInfinity = InfinityType::Constant;
    InfinityType postInfinity = InfinityType::Constant;
};

class AnimCurve {
public:
    explicit AnimCurve(AnimCurveData data);

    // The curve's value at `x` (a time in frames or a driver value). An empty curve returns 0.
    // Never throws; non-finite x returns the nearest end's constant value.
    double evaluate(double x) const;

    size_t keyCount() const { return m_keys.size(); }
    const AnimKey& key(size_t i) const { return m_keys[i]; }
    // The resolved slopes (value per input unit) on each side of key i, after tangent-type rules.
    double inSlope(size_t i) const { return m_tangents[i].inSlope; }
    double outSlope(size_t i) const { return m_tangents[i].outSlope; }

private:
    struct Resolved {
        double inSlope = 0.0, outSlope = 0.0;
        // Control-point offsets: the out control point of key i is (t + outDx, v + outDy), the in
        // control point (t − inDx, v − inDy). Non-weighted curves use a third of the neighbouring span.
        double inDx = 0.0, inDy = 0.0, outDx = 0.0, outDy = 0.0;
    };
    void resolveTangents();
    double evaluateInRange(double x) const;
    double segment(size_t i, double x) const;  // between key i and i + 1

    std::vector<AnimKey> m_keys;
    std::vector<Resolved> m_tangents;
    TangentType m_tangentType;
    bool m_weighted;
    InfinityType m_pre, m_post;
};

}  // namespace pushpin::scene
