#include "core/render/shape_geometry.h"

#include "core/scene/nurbs_eval.h"

#include <algorithm>
#include <cmath>
#include <new>

namespace pushpin::render {

using scene::Graph;
using scene::NodeId;

void evaluateShape(scene::Evaluator& ev, NodeId shape, const std::string& label, ShapeGeometry& out,
                   std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    try {
        if (g.node(shape).type == "mesh") {
            out.evaluation = scene::evaluateMeshShape(ev, shape);
            for (const std::string& note : out.evaluation.notes) notes.push_back(label + ": " + note);
            if (!out.evaluation.mesh) {
                out.failed = true;
                out.skipReason =
                    out.evaluation.skipReason.empty() ? "the mesh could not be evaluated" : out.evaluation.skipReason;
                return;
            }
            // The evaluation has validated the mesh when nothing changed it afterwards.
            geom::MeshValidation validation;
            if (out.evaluation.degenerateFaces) validation.degenerateFaces = std::move(*out.evaluation.degenerateFaces);
            else validation = out.evaluation.mesh->validate();
            out.evaluation.degenerateFaces.reset();
            auto mesh = std::make_shared<const geom::Mesh>(std::move(*out.evaluation.mesh));
            out.evaluation.mesh.reset();
            if (!validation.ok()) {
                out.failed = true;
                out.skipReason = "invalid mesh: " + validation.errors.front();
                return;
            }
            if (mesh->empty()) {
                out.failed = true;
                out.skipReason = "mesh has no faces";
                return;
            }
            if (!validation.degenerateFaces.empty()) {
                auto degenerate = std::make_shared<std::vector<bool>>(mesh->faceCount(), false);
                for (uint32_t f : validation.degenerateFaces) (*degenerate)[f] = true;
                out.degenerate = std::move(degenerate);
                notes.push_back(label + ": " + std::to_string(validation.degenerateFaces.size()) +
                                " degenerate face(s) not rendered");
            }
            out.mesh = std::move(mesh);
            return;
        }
        std::string reason, note;
        auto surface = scene::evaluateNurbsSurface(ev, shape, &reason, &note);
        if (!note.empty()) notes.push_back(label + ": " + note);
        if (!surface) {
            out.failed = true;
            out.skipReason = reason.empty() ? "the surface could not be evaluated" : reason;
            return;
        }
        out.divU = spanDivisions(ev, shape, "numberU", "uDivisionsFactor", label, notes);
        out.divV = spanDivisions(ev, shape, "numberV", "vDivisionsFactor", label, notes);
        out.surface = std::make_shared<const geom::NurbsSurface>(std::move(*surface));
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        out.failed = true;
        out.skipReason = e.what();
    }
}

int spanDivisions(scene::Evaluator& ev, NodeId shape, const char* numberAttr, const char* factorAttr,
                  const std::string& label, std::vector<std::string>& notes) {
    constexpr int kMaxDivisions = 256;
    double number = ev.getDouble(shape, numberAttr, 3.0);
    double factor = ev.getDouble(shape, factorAttr, 1.5);
    if (!std::isfinite(number) || !std::isfinite(factor)) {
        notes.push_back(label + ": non-finite " + numberAttr + " or " + factorAttr + " replaced by the defaults");
        number = 3.0;
        factor = 1.5;
    }
    const double divisions = std::ceil(number * factor - 1e-9);
    if (divisions > kMaxDivisions) {
        notes.push_back(label + ": " + numberAttr + " × " + factorAttr + " capped at " + std::to_string(kMaxDivisions) +
                        " divisions per span");
        return kMaxDivisions;
    }
    return std::max(1, int(divisions));
}

}  // namespace pushpin::render
