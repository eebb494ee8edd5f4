// core/geom/nurbs.h: NURBS curves and surfaces as exact geometry: textbook knot vectors, homogeneous
// control points, point and first-derivative evaluation (Cox–de Boor basis functions, rational
// division), control-hull bounds and validation with readable messages.
// Thread safety: objects are immutable after creation; every const member may be called from many
// threads at once. Memory: a surface owns its knots and CVs (32 bytes per CV); evaluation allocates
// nothing.
//
// Conventions (Piegl & Tiller, "The NURBS Book", 2nd ed., chapters 2–4):
// - Knot vectors are the full textbook vectors: cvCount + degree + 1 knots. Maya files store two
//   fewer (the outermost knot at each end, which never influences the curve on its domain);
//   `textbookKnotsFromMaya` restores them.
// - Control points are homogeneous and pre-multiplied: (x·w, y·w, z·w, w). A non-rational CV has
//   w = 1. Weights must be positive and finite.
// - Surface CVs are U-major: cv(i, j) = cvs[i * cvCountV + j] (V varies fastest), as Maya writes them.
// - Periodic directions store their `degree` wrap-around CVs explicitly; evaluation treats every
//   form the same way (the knot vector and the repeated CVs make the wrap seamless).
// - The parameter domain of a direction is [knots[degree], knots[cvCount]]; parameters outside it
//   are clamped (open/closed) or wrapped into it (periodic).
#pragma once

#include "core/geom/bounds.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pushpin::geom {

// Highest degree evaluation supports (Maya offers 1, 2, 3, 5 and 7).
constexpr int kMaxNurbsDegree = 15;

enum class NurbsForm : unsigned char { Open = 0, Closed = 1, Periodic = 2 };

const char* nurbsFormName(NurbsForm form);

// Textbook knot vector from Maya's (which omits one knot at each end): one knot added at each end.
// Open/closed: the end knots are repeated (t0 = t1, tLast = tLast-1), the clamped vector Maya implies.
// Periodic: the vector is extended by the knot spacing one period away, t0 = t1 − (t[1+s] − t[s]) with
// s = the number of spans, so a uniform periodic vector stays uniform; when the vector is too short
// for that, by its first/last spacing. The added knots never influence the curve on its domain.
// An empty input gives an empty output.
std::vector<double> textbookKnotsFromMaya(const std::vector<double>& mayaKnots, int degree, NurbsForm form);
// Maya's knot vector from a textbook one: the first and last knots dropped.
std::vector<double> mayaKnotsFromTextbook(const std::vector<double>& knots);

// Index i of the knot span [knots[i], knots[i+1]) holding t, with degree <= i <= cvCount − 1; t at the
// domain end maps to the last non-empty span. Precondition: a valid knot vector (see validateKnots).
int findKnotSpan(int degree, const std::vector<double>& knots, int cvCount, double t);
// The degree + 1 non-zero basis functions N[span−degree .. span] at t (The NURBS Book A2.2) into `out`,
// and, when `derivs` is not null, their first derivatives. Both arrays hold degree + 1 values.
void basisFunctions(int span, double t, int degree, const std::vector<double>& knots, double* out,
                    double* derivs = nullptr);

// Empty when `knots` is a usable knot vector for `cvCount` CVs of `degree`: 1 <= degree <= kMaxNurbsDegree,
// cvCount >= degree + 1, cvCount + degree + 1 knots, all finite, non-decreasing, non-empty domain.
// Otherwise a message that names `direction` ("U", "V" or "curve") and the offending values.
std::string validateKnots(const std::vector<double>& knots, int degree, int cvCount, const char* direction);

// A point of a curve or surface with its first derivatives (object space, per unit parameter).
struct NurbsSurfacePoint {
    glm::dvec3 position{0.0};
    glm::dvec3 dPdu{0.0};
    glm::dvec3 dPdv{0.0};
    // Unit normal dPdu × dPdv; zero where the surface is degenerate (a pole), see NurbsSurface::normal.
    glm::dvec3 normal() const;
};

class NurbsCurve {
public:
    // Builds a curve; returns nullopt and sets *error (when not null) if the data is invalid
    // (see validateKnots; cvs must be finite with w > 0).
    static std::optional<NurbsCurve> create(int degree, NurbsForm form, std::vector<double> knots,
                                            std::vector<glm::dvec4> cvs, bool rational, std::string* error);

    int degree() const { return m_degree; }
    NurbsForm form() const { return m_form; }
    bool rational() const { return m_rational; }
    const std::vector<double>& knots() const { return m_knots; }
    const std::vector<glm::dvec4>& cvs() const { return m_cvs; }  // homogeneous, pre-multiplied
    int cvCount() const { return int(m_cvs.size()); }
    int spans() const { return cvCount() - m_degree; }
    double tMin() const { return m_knots[m_degree]; }
    double tMax() const { return m_knots[cvCount()]; }

    glm::dvec3 point(double t) const;
    // Position and first derivative dC/dt.
    void evaluate(double t, glm::dvec3* position, glm::dvec3* derivative) const;
    // Bounds of the control polygon (the curve lies inside it for positive weights).
    Bounds3 bounds() const;

private:
    NurbsCurve() = default;
    double normalizedParameter(double t) const;
    int m_degree = 1;
    NurbsForm m_form = NurbsForm::Open;
    bool m_rational = false;
    std::vector<double> m_knots;
    std::vector<glm::dvec4> m_cvs;
};

class NurbsSurface {
public:
    // Builds a surface from textbook knot vectors and cvCountU × cvCountV homogeneous CVs (U-major).
    // Returns nullopt and sets *error (when not null) if anything is inconsistent: degrees, knot counts
    // (cvCount + degree + 1), decreasing or non-finite knots, CV count, non-finite CVs, weights <= 0.
    static std::optional<NurbsSurface> create(int degreeU, int degreeV, NurbsForm formU, NurbsForm formV,
                                              std::vector<double> knotsU, std::vector<double> knotsV,
                                              int cvCountU, int cvCountV, std::vector<glm::dvec4> cvs,
                                              bool rational, std::string* error);

    int degreeU() const { return m_degreeU; }
    int degreeV() const { return m_degreeV; }
    NurbsForm formU() const { return m_formU; }
    NurbsForm formV() const { return m_formV; }
    bool rational() const { return m_rational; }
    const std::vector<double>& knotsU() const { return m_knotsU; }
    const std::vector<double>& knotsV() const { return m_knotsV; }
    int cvCountU() const { return m_cvCountU; }
    int cvCountV() const { return m_cvCountV; }
    int spansU() const { return m_cvCountU - m_degreeU; }
    int spansV() const { return m_cvCountV - m_degreeV; }
    const std::vector<glm::dvec4>& cvs() const { return m_cvs; }  // homogeneous, pre-multiplied, U-major
    const glm::dvec4& cv(int i, int j) const { return m_cvs[size_t(i) * size_t(m_cvCountV) + size_t(j)]; }
    // Cartesian position of CV (i, j): xyz / w.
    glm::dvec3 cvPoint(int i, int j) const;
    double uMin() const { return m_knotsU[m_degreeU]; }
    double uMax() const { return m_knotsU[m_cvCountU]; }
    double vMin() const { return m_knotsV[m_degreeV]; }
    double vMax() const { return m_knotsV[m_cvCountV]; }

    glm::dvec3 point(double u, double v) const;
    // Position and first partial derivatives at (u, v).
    NurbsSurfacePoint evaluate(double u, double v) const;
    // Unit normal at (u, v). Where dPdu × dPdv vanishes (poles of a sphere, apex of a cone) the
    // normal is taken a small step inside the domain, towards the middle; zero if still degenerate.
    glm::dvec3 normal(double u, double v) const;
    // Bounds of the CVs (the surface lies in their convex hull for positive weights).
    Bounds3 bounds() const;

private:
    NurbsSurface() = default;
    double clampU(double u) const;
    double clampV(double v) const;
    int m_degreeU = 1, m_degreeV = 1;
    NurbsForm m_formU = NurbsForm::Open, m_formV = NurbsForm::Open;
    bool m_rational = false;
    std::vector<double> m_knotsU, m_knotsV;
    int m_cvCountU = 0, m_cvCountV = 0;
    std::vector<glm::dvec4> m_cvs;
};

}  // namespace pushpin::geom
