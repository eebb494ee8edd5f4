#include "core/scene/anim_curve.h"

#include <algorithm>
#include <cmath>

// What is known and what is inferred about Maya's curves:
// - Segment shape: a cubic Bézier through the two keys with inner control points a third of each
//   tangent vector away (Hermite when tangents are not weighted) — Autodesk's open-source animX.
// - Tangent enums and units: taken from files Maya wrote (visibility curves carry kot 5 = step;
//   `.tan` 10 before 2017, 18 after; kix/kox in seconds and kiy/koy in internal units, which the
//   caller converts).
// - Spline, linear, flat and step rules are Maya's documented behaviour. The clamped tolerance, the
//   plateau overshoot test and the auto limits follow public re-implementations (animX's auto
//   tangent; an open-source DCC's clamped and plateau rules); Maya's own code is not public.
// - keyTanLocked and keyWeightLocked only constrain editing (both tangents are stored), so they do not
//   enter evaluation; rotation curves are evaluated per channel (independent Euler curves).
namespace pushpin::scene {

namespace {

// The steepest slope a tangent may have: tan(89.99999°), the limit Maya's API reports for vertical
// tangents. Keeps Hermite segments finite when a tangent's x is zero.
constexpr double kMaxSlope = 5729577.9485111479;

// Clamped tangents turn flat on the side of a neighbour whose value is within this distance of the
// key's value. The constant and the rule come from a public re-implementation of Maya's tangent
// rules; Maya's own code is not public. It is applied to values in the curve's internal units.
constexpr double kClampedTolerance = 0.05;

double slopeOf(double dy, double dx) {
    if (std::abs(dx) < 1e-12) return dy == 0.0 ? 0.0 : std::copysign(kMaxSlope, dy);
    return std::clamp(dy / dx, -kMaxSlope, kMaxSlope);
}

// Sign that counts zero as positive, as the auto-tangent rule needs.
int signNoZero(double v) { return v < 0.0 ? -1 : 1; }

}  // namespace

TangentType tangentTypeFromInt(int v) {
    switch (v) {
        case 1: case 2: case 3: case 5: case 6: case 7: case 9: case 10: case 16: case 17: case 18:
        case 27: case 28: case 29: return static_cast<TangentType>(v);
        default: return TangentType::Global;
    }
}

InfinityType infinityTypeFromInt(int v) {
    switch (v) {
        case 1: case 3: case 4: case 5: return static_cast<InfinityType>(v);
        default: return InfinityType::Constant;
    }
}

AnimCurve::AnimCurve(AnimCurveData data)
    : m_keys(std::move(data.keys)),
      m_tangentType(data.tangentType),
      m_weighted(data.weightedTangents),
      m_pre(data.preInfinity),
      m_post(data.postInfinity) {
    // Resolve the curve-level default first so that per-key Global falls back to something concrete.
    if (m_tangentType == TangentType::Global) m_tangentType = TangentType::Clamped;
    std::stable_sort(m_keys.begin(), m_keys.end(), [](const AnimKey& a, const AnimKey& b) { return a.time < b.time; });
    for (AnimKey& k : m_keys) {
        auto effective = [&](TangentType t) {
            switch (t) {
                case TangentType::Global: return m_tangentType;
                case TangentType::Slow:
                case TangentType::Fast: return TangentType::Spline;
                case TangentType::AutoMix:
                case TangentType::AutoEase:
                case TangentType::AutoCustom: return TangentType::Auto;
                default: return t;
            }
        };
        k.inType = effective(k.inType);
        k.outType = effective(k.outType);
        if (k.inType == TangentType::Global) k.inType = TangentType::Clamped;
        if (k.outType == TangentType::Global) k.outType = TangentType::Clamped;
    }
    resolveTangents();
}

void AnimCurve::resolveTangents() {
    const size_t n = m_keys.size();
    m_tangents.assign(n, Resolved{});
    for (size_t i = 0; i < n; ++i) {
        const AnimKey& k = m_keys[i];
        const bool hasPrev = i > 0, hasNext = i + 1 < n;
        const AnimKey* prev = hasPrev ? &m_keys[i - 1] : nullptr;
        const AnimKey* next = hasNext ? &m_keys[i + 1] : nullptr;
        const double hIn = hasPrev ? k.time - prev->time : 0.0;
        const double hOut = hasNext ? next->time - k.time : 0.0;
        const double chordIn = hasPrev ? slopeOf(k.value - prev->value, hIn) : 0.0;
        const double chordOut = hasNext ? slopeOf(next->value - k.value, hOut) : 0.0;

        // Spline (Catmull-Rom-like): the slope between the two neighbours; an end key takes the slope
        // towards its only neighbour (a two-key spline or clamped curve is a straight line, as in Maya).
        double spline = 0.0;
        if (hasPrev && hasNext) spline = slopeOf(next->value - prev->value, next->time - prev->time);
        else if (hasPrev) spline = chordIn;
        else if (hasNext) spline = chordOut;

        // Clamped: like spline, flat when a neighbour's value (almost) equals the key's, which stops
        // the curve overshooting a hold.
        const bool clampFlat = (hasPrev && std::abs(prev->value - k.value) <= kClampedTolerance) ||
                               (hasNext && std::abs(next->value - k.value) <= kClampedTolerance);

        // Auto (Maya 2017+): the spline slope limited so that neither control point passes the value
        // of the neighbouring key; flat at the ends and at extrema.
        double autoSlope = 0.0;
        if (hasPrev && hasNext) {
            const double prev3 = 3.0 * slopeOf(k.value - prev->value, hIn);
            const double next3 = 3.0 * slopeOf(next->value - k.value, hOut);
            if (signNoZero(prev3) != signNoZero(next3) || signNoZero(spline) != signNoZero(next3))
                autoSlope = 0.0;
            else if (next3 >= 0.0)
                autoSlope = std::min({spline, next3, prev3});
            else
                autoSlope = std::max({spline, next3, prev3});
        }

        // Plateau: flat at the ends and at extrema; elsewhere the spline slope unless its control point
        // on that side would pass the neighbouring value (or the mirrored value of the other neighbour
        // when that side is steeper), in which case that side is flat.
        double plateauIn = 0.0, plateauOut = 0.0;
        if (hasPrev && hasNext && (prev->value - k.value) * (next->value - k.value) < 0.0 && hIn > 0.0 && hOut > 0.0) {
            const double dPrev = std::abs(prev->value - k.value), dNext = std::abs(next->value - k.value);
            const double allowIn = std::min(dPrev, dNext * hIn / hOut);
            const double allowOut = std::min(dNext, dPrev * hOut / hIn);
            plateauIn = std::abs(spline) * hIn / 3.0 > allowIn ? 0.0 : spline;
            plateauOut = std::abs(spline) * hOut / 3.0 > allowOut ? 0.0 : spline;
        }

        auto slopeFor = [&](TangentType type, bool inSide) -> double {
            switch (type) {
                case TangentType::Fixed:
                    if (inSide) return k.hasInTangent ? slopeOf(k.inY, k.inX) : 0.0;
                    return k.hasOutTangent ? slopeOf(k.outY, k.outX) : 0.0;
                case TangentType::Linear:
                    // Towards the neighbour on that side; an end key continues the other side's line
                    // (so linear tangents with linear infinity extend the first/last span).
                    if (inSide) return hasPrev ? chordIn : chordOut;
                    return hasNext ? chordOut : chordIn;
                case TangentType::Spline: return spline;
                case TangentType::Clamped: return clampFlat ? 0.0 : spline;
                case TangentType::Plateau: return inSide ? plateauIn : plateauOut;
                case TangentType::Auto: return autoSlope;
                case TangentType::Flat:
                case TangentType::Step:
                case TangentType::StepNext:
                default: return 0.0;
            }
        };

        Resolved& r = m_tangents[i];
        r.inSlope = slopeFor(k.inType, true);
        r.outSlope = slopeFor(k.outType, false);

        // Control points. Non-weighted curves: a third of the span (a cubic Hermite segment). Weighted
        // curves: a third of the stored tangent vector; for computed tangent types the stored x gives
        // the length and the type the direction (when no x is stored, the span length, which is what
        // Maya writes for new weighted keys).
        if (!m_weighted) {
            r.inDx = hIn / 3.0;
            r.inDy = r.inSlope * r.inDx;
            r.outDx = hOut / 3.0;
            r.outDy = r.outSlope * r.outDx;
        } else {
            if (k.inType == TangentType::Fixed && k.hasInTangent) {
                r.inDx = std::max(0.0, k.inX) / 3.0;
                r.inDy = k.inY / 3.0;
            } else {
                const double len = (k.hasInTangent && k.inX > 0.0) ? k.inX : hIn;
                r.inDx = len / 3.0;
                r.inDy = r.inSlope * r.inDx;
            }
            if (k.outType == TangentType::Fixed && k.hasOutTangent) {
                r.outDx = std::max(0.0, k.outX) / 3.0;
                r.outDy = k.outY / 3.0;
            } else {
                const double len = (k.hasOutTangent && k.outX > 0.0) ? k.outX : hOut;
                r.outDx = len / 3.0;
                r.outDy = r.outSlope * r.outDx;
            }
        }
    }
}

double AnimCurve::segment(size_t i, double x) const {
    const AnimKey& a = m_keys[i];
    const AnimKey& b = m_keys[i + 1];
    const double h = b.time - a.time;
    if (h <= 0.0) return b.value;
    // The span's interpolation is decided by the start key's out tangent (and, for a straight line,
    // the end key's in tangent as well).
    if (a.outType == TangentType::Step) return a.value;
    if (a.outType == TangentType::StepNext) return b.value;
    const double u = std::clamp((x - a.time) / h, 0.0, 1.0);
    if (a.outType == TangentType::Linear && b.inType == TangentType::Linear) return a.value + (b.value - a.value) * u;

    const Resolved& ra = m_tangents[i];
    const Resolved& rb = m_tangents[i + 1];
    if (!m_weighted) {
        // Cubic Hermite with slopes in value per input unit.
        const double u2 = u * u, u3 = u2 * u;
        const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
        return h00 * a.value + h10 * h * ra.outSlope + h01 * b.value + h11 * h * rb.inSlope;
    }

    // Weighted: a 2D cubic Bézier in (time, value) solved for the parameter whose time is x. The
    // control points' times are kept inside the span and in order so that time is monotonic in the
    // parameter (inferred: Maya also keeps an animation curve a function of time).
    double dx1 = std::max(0.0, ra.outDx), dy1 = ra.outDy;
    double dx2 = std::max(0.0, rb.inDx), dy2 = rb.inDy;
    if (dx1 + dx2 > h) {
        const double s = h / (dx1 + dx2);
        dx1 *= s;
        dy1 *= s;
        dx2 *= s;
        dy2 *= s;
    }
    const double x0 = a.time, x1 = a.time + dx1, x2 = b.time - dx2, x3 = b.time;
    const double y0 = a.value, y1 = a.value + dy1, y2 = b.value - dy2, y3 = b.value;
    auto bez = [](double p0, double p1, double p2, double p3, double s) {
        const double t = 1.0 - s;
        return t * t * t * p0 + 3 * t * t * s * p1 + 3 * t * s * s * p2 + s * s * s * p3;
    };
    auto bezDeriv = [](double p0, double p1, double p2, double p3, double s) {
        const double t = 1.0 - s;
        return 3 * t * t * (p1 - p0) + 6 * t * s * (p2 - p1) + 3 * s * s * (p3 - p2);
    };
    // Newton steps safeguarded by bisection on the monotonic x(s).
    double lo = 0.0, hi = 1.0, s = u;
    for (int iter = 0; iter < 64; ++iter) {
        const double fx = bez(x0, x1, x2, x3, s) - x;
        if (std::abs(fx) < 1e-12 * std::max(1.0, std::abs(h))) break;
        if (fx > 0.0) hi = s;
        else lo = s;
        const double d = bezDeriv(x0, x1, x2, x3, s);
        double next = d > 0.0 ? s - fx / d : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (hi - lo < 1e-15) break;
        s = next;
    }
    return bez(y0, y1, y2, y3, s);
}

double AnimCurve::evaluateInRange(double x) const {
    // Key i with time(i) <= x < time(i + 1); x equal to a key time returns that key's value.
    auto it = std::upper_bound(m_keys.begin(), m_keys.end(), x, [](double v, const AnimKey& k) { return v < k.time; });
    if (it == m_keys.begin()) return m_keys.front().value;
    const size_t i = size_t(it - m_keys.begin()) - 1;
    if (i + 1 >= m_keys.size() || m_keys[i].time == x) return m_keys[i].value;
    return segment(i, x);
}

double AnimCurve::evaluate(double x) const {
    if (m_keys.empty()) return 0.0;
    const AnimKey& first = m_keys.front();
    const AnimKey& last = m_keys.back();
    if (std::isnan(x)) return first.value;
    if (x == -INFINITY) return first.value;
    if (x == INFINITY) return last.value;
    if (x >= first.time && x <= last.time) return evaluateInRange(x);

    const bool before = x < first.time;
    const InfinityType mode = before ? m_pre : m_post;
    const double range = last.time - first.time;
    if (mode == InfinityType::Constant || range <= 0.0) return before ? first.value : last.value;
    if (mode == InfinityType::Linear) {
        // Continues along the end key's outer tangent.
        if (before) return first.value - (first.time - x) * m_tangents.front().inSlope;
        return last.value + (x - last.time) * m_tangents.back().outSlope;
    }

    // Cycle index c (negative before the keys) and the phase within the cycle, in [0, range].
    const double c = std::floor((x - first.time) / range);
    const double phase = std::clamp(x - first.time - c * range, 0.0, range);
    if (mode == InfinityType::Oscillate) {
        // Odd cycles run backwards, so the curve mirrors at each end of the key range.
        const bool odd = std::fmod(std::abs(c), 2.0) == 1.0;
        return evaluateInRange(odd ? last.time - phase : first.time + phase);
    }
    const double v = evaluateInRange(first.time + phase);
    if (mode == InfinityType::CycleRelative) return v + c * (last.value - first.value);
    return v;  // Cycle
}

}  // namespace pushpin::scene
