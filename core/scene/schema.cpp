// The node-type table. Names, types and defaults come from reference/nodes.md and
// reference/render-globals.md (Maya's attribute metadata and node documentation).
#include "core/scene/schema.h"

#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>

namespace pushpin::scene {

int componentCount(AttrType type) {
    switch (type) {
        case AttrType::Bool: case AttrType::Int: case AttrType::Enum:
        case AttrType::Float: case AttrType::Double: return 1;
        case AttrType::Double2: case AttrType::Float2: case AttrType::Long2: case AttrType::Short2: return 2;
        case AttrType::Double3: case AttrType::Float3: case AttrType::Long3: case AttrType::Short3: return 3;
        case AttrType::Double4: return 4;
        default: return 0;
    }
}

NodeSchema::NodeSchema(std::string type, const NodeSchema* base) : m_type(std::move(type)), m_base(base) {}

const AttrSpec* NodeSchema::find(std::string_view name) const {
    auto it = m_byName.find(name);
    return it == m_byName.end() ? nullptr : it->second;
}

bool NodeSchema::isA(std::string_view type) const {
    for (const NodeSchema* s = this; s; s = s->m_base)
        if (s->m_type == type) return true;
    return false;
}

void NodeSchema::add(AttrSpec spec) { m_attrs.push_back(std::move(spec)); }

void NodeSchema::finalize() {
    m_dag = isA("dagNode");
    m_byName.clear();
    for (const NodeSchema* s = this; s; s = s->m_base)
        for (const AttrSpec& spec : s->m_attrs) {
            m_byName.emplace(spec.longName, &spec);
            if (!spec.shortName.empty()) m_byName.emplace(spec.shortName, &spec);
        }
}

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
using T = AttrType;
using U = UnitKind;

class Table {
public:
    NodeSchema& type(const std::string& name, const std::string& base = "") {
        const NodeSchema* b = base.empty() ? nullptr : m_types.at(base).get();
        auto& slot = m_types[name];
        slot = std::make_unique<NodeSchema>(name, b);
        m_current = slot.get();
        return *slot;
    }
    // A scalar or data attribute on the current type.
    Table& a(const char* ln, const char* sn, T t, double def = 0.0, U unit = U::None, bool multi = false,
             const char* parent = "") {
        AttrSpec s;
        s.longName = ln;
        s.shortName = sn;
        s.type = t;
        s.unit = unit;
        s.multi = multi;
        s.parent = parent;
        s.defaults = {def, def, def, def};
        m_current->add(std::move(s));
        return *this;
    }
    // A numeric compound with named component children, e.g. translate (t) = tx ty tz.
    Table& c(const char* ln, const char* sn, T t, std::array<double, 4> def, U unit,
             std::initializer_list<std::pair<const char*, const char*>> children, bool multi = false,
             const char* parent = "") {
        AttrSpec s;
        s.longName = ln;
        s.shortName = sn;
        s.type = t;
        s.unit = unit;
        s.multi = multi;
        s.parent = parent;
        s.defaults = def;
        m_current->add(s);
        int k = 0;
        for (auto& [cl, cs] : children) {
            AttrSpec child;
            child.longName = cl;
            child.shortName = cs;
            child.type = (t == T::Float2 || t == T::Float3) ? T::Float
                         : (t == T::Long2 || t == T::Long3 || t == T::Short2 || t == T::Short3) ? T::Int
                                                                                                : T::Double;
            child.unit = unit;
            child.parent = ln;
            child.component = k;
            child.defaults = {def[size_t(k)], def[size_t(k)], def[size_t(k)], def[size_t(k)]};
            m_current->add(std::move(child));
            ++k;
        }
        return *this;
    }
    Table& color(const char* ln, const char* sn, double r, double g, double b, const char* p = nullptr,
                 bool multi = false, const char* parent = "") {
        // Maya names colour children <long>R/G/B and <short>r/g/b (colorR/cr …).
        std::string base(ln), sbase(sn), prefix = p ? p : sn;
        m_names.push_back(base + "R");
        m_names.push_back(base + "G");
        m_names.push_back(base + "B");
        m_names.push_back(prefix + "r");
        m_names.push_back(prefix + "g");
        m_names.push_back(prefix + "b");
        auto it = m_names.end() - 6;
        return c(ln, sn, T::Float3, {r, g, b, 0}, U::None,
                 {{it[0].c_str(), it[3].c_str()}, {it[1].c_str(), it[4].c_str()}, {it[2].c_str(), it[5].c_str()}},
                 multi, parent);
    }
    Table& xyz(const char* ln, const char* sn, T t, double x, double y, double z, U unit) {
        std::string base(ln), sbase(sn);
        m_names.push_back(base + "X");
        m_names.push_back(base + "Y");
        m_names.push_back(base + "Z");
        m_names.push_back(sbase + "x");
        m_names.push_back(sbase + "y");
        m_names.push_back(sbase + "z");
        auto it = m_names.end() - 6;
        return c(ln, sn, t, {x, y, z, 0}, unit,
                 {{it[0].c_str(), it[3].c_str()}, {it[1].c_str(), it[4].c_str()}, {it[2].c_str(), it[5].c_str()}});
    }

    std::map<std::string, std::unique_ptr<NodeSchema>, std::less<>> m_types;
    // The same types by name for lookups, filled once the table is complete (the views point at
    // the keys of m_types, whose nodes never move).
    std::unordered_map<std::string_view, const NodeSchema*> m_byType;

private:
    NodeSchema* m_current = nullptr;
    std::deque<std::string> m_names;  // stable storage for generated child names while building
};

void addDagTypes(Table& t) {
    t.type("node");
    t.a("message", "msg", T::Message).a("caching", "cch", T::Bool).a("frozen", "fzn", T::Bool)
        .a("isHistoricallyInteresting", "ihi", T::Int, 2).a("nodeState", "nds", T::Enum)
        .a("binMembership", "bnm", T::Message);

    t.type("dagNode", "node");
    t.a("boundingBox", "bb", T::Compound)
        .a("visibility", "v", T::Bool, 1).a("template", "tmp", T::Bool).a("lodVisibility", "lodv", T::Bool, 1)
        .a("intermediateObject", "io", T::Bool).a("ghosting", "gh", T::Bool)
        .a("instObjGroups", "iog", T::Compound, 0, U::None, true)
        .a("objectGroups", "og", T::Compound, 0, U::None, true, "instObjGroups")
        .a("objectGrpCompList", "gcl", T::ComponentList, 0, U::None, false, "objectGroups")
        .a("objectGroupId", "gid", T::Int, 0, U::None, false, "objectGroups")
        .a("objectGrpColor", "gco", T::Int, 0, U::None, false, "objectGroups")
        .a("worldMatrix", "wm", T::Matrix, 0, U::None, true).a("worldInverseMatrix", "wim", T::Matrix, 0, U::None, true)
        .a("parentMatrix", "pm", T::Matrix, 0, U::None, true).a("matrix", "m", T::Matrix)
        .a("overrideEnabled", "ove", T::Bool).a("overrideVisibility", "ovv", T::Bool, 1)
        .a("overrideDisplayType", "ovdt", T::Enum).a("overrideLevelOfDetail", "ovlod", T::Enum)
        .a("overrideShading", "ovs", T::Bool, 1).a("overrideTexturing", "ovt", T::Bool, 1)
        .a("overridePlayback", "ovp", T::Bool, 1).a("overrideColor", "ovc", T::Int)
        .a("useObjectColor", "uoc", T::Enum).a("objectColor", "oc", T::Int)
        .a("drawOverride", "do", T::Compound).a("renderInfo", "ri", T::Compound)
        .a("identification", "rlid", T::Int).a("layerRenderable", "rndr", T::Bool, 1)
        .a("layerOverrideColor", "lovc", T::Int).a("renderLayerInfo", "rlio", T::Compound, 0, U::None, true);

    t.type("transform", "dagNode");
    t.xyz("translate", "t", T::Double3, 0, 0, 0, U::Distance)
        .xyz("rotate", "r", T::Double3, 0, 0, 0, U::Angle)
        .xyz("scale", "s", T::Double3, 1, 1, 1, U::None)
        .c("shear", "sh", T::Double3, {0, 0, 0, 0}, U::None, {{"shearXY", "shxy"}, {"shearXZ", "shxz"}, {"shearYZ", "shyz"}})
        .a("rotateOrder", "ro", T::Enum)
        .xyz("rotateAxis", "ra", T::Double3, 0, 0, 0, U::Angle)
        .xyz("rotatePivot", "rp", T::Double3, 0, 0, 0, U::Distance)
        .xyz("rotatePivotTranslate", "rpt", T::Double3, 0, 0, 0, U::Distance)
        .xyz("scalePivot", "sp", T::Double3, 0, 0, 0, U::Distance)
        .xyz("scalePivotTranslate", "spt", T::Double3, 0, 0, 0, U::Distance)
        .a("inheritsTransform", "it", T::Bool, 1).a("displayHandle", "dh", T::Bool)
        .a("displayScalePivot", "dsp", T::Bool).a("displayRotatePivot", "drp", T::Bool)
        .a("displayLocalAxis", "dla", T::Bool).a("dynamics", "dyn", T::Bool)
        .a("showManipDefault", "smd", T::Enum).a("specifiedManipLocation", "sml", T::Enum)
        .xyz("selectHandle", "hdl", T::Double3, 0, 0, 0, U::Distance)
        .a("xformMatrix", "xm", T::Matrix).a("minTransLimit", "mntl", T::Double3)
        .a("maxTransLimit", "mxtl", T::Double3).a("minTransLimitEnable", "mtxe", T::Compound)
        .a("blackBox", "bbx", T::Bool).a("rotationInterpolation", "roi", T::Enum, 1);

    t.type("joint", "transform");
    t.xyz("jointOrient", "jo", T::Double3, 0, 0, 0, U::Angle)
        .a("segmentScaleCompensate", "ssc", T::Bool, 1)
        .xyz("inverseScale", "is", T::Double3, 1, 1, 1, U::None)
        .a("radius", "radi", T::Double, 1).a("drawStyle", "ds", T::Enum)
        .c("stiffness", "st", T::Double3, {0, 0, 0, 0}, U::None, {{"stiffnessX", "stx"}, {"stiffnessY", "sty"}, {"stiffnessZ", "stz"}})
        .a("preferredAngle", "pa", T::Double3, 0, U::Angle).a("jointType", "jt", T::String)
        .a("side", "sd", T::Enum).a("type", "typ", T::Enum).a("otherType", "otp", T::String);

    t.type("shape", "dagNode");
    t.type("geometryShape", "shape");
    t.a("castsShadows", "csh", T::Bool, 1).a("receiveShadows", "rcsh", T::Bool, 1)
        .a("motionBlur", "mb", T::Bool, 1).a("primaryVisibility", "vis", T::Bool, 1)
        .a("smoothShading", "smo", T::Bool, 1).a("visibleInReflections", "vir", T::Bool, 0)
        .a("visibleInRefractions", "vif", T::Bool, 0).a("doubleSided", "ds", T::Bool, 1)
        .a("opposite", "op", T::Bool, 0).a("geometryAntialiasingOverride", "gao", T::Bool)
        .a("antialiasingLevel", "gal", T::Int, 1).a("shadingSamplesOverride", "sso", T::Bool)
        .a("shadingSamples", "ssa", T::Int, 1).a("maxShadingSamples", "msa", T::Int, 1)
        .a("maxVisibilitySamplesOverride", "vbo", T::Bool).a("maxVisibilitySamples", "mvs", T::Int, 1)
        .a("volumeSamplesOverride", "vso", T::Bool).a("volumeSamples", "vss", T::Int, 1)
        .a("depthJitter", "dej", T::Bool).a("ignoreSelfShadowing", "iss", T::Bool)
        .a("boundingBoxScale", "bbs", T::Double3, 1.5).a("featureDisplacement", "fbda", T::Bool, 1)
        .a("displacementThreshold", "dsr", T::Double, 0.0).a("initialSampleRate", "dfs", T::Int, 6)
        .a("extraSampleRate", "xsr", T::Int, 5).a("textureThreshold", "tsrs", T::Double)
        .a("normalThreshold", "nat", T::Double, 30 * kDeg, U::Angle)
        .a("compInstObjGroups", "ciog", T::Compound, 0, U::None, true);
    t.type("surfaceShape", "geometryShape");
    t.type("deformableShape", "surfaceShape");
    t.type("controlPoint", "deformableShape");
    t.c("controlPoints", "cp", T::Double3, {0, 0, 0, 0}, U::Distance, {{"xValue", "xv"}, {"yValue", "yv"}, {"zValue", "zv"}}, true)
        .a("weights", "wt", T::Double, 0, U::None, true)
        .a("tweak", "tw", T::Bool).a("relativeTweak", "rtw", T::Bool, 1).a("currentUVSet", "cuvs", T::String)
        .a("displayImmediate", "di", T::Bool).a("displayColors", "dcol", T::Bool)
        .a("displayColorChannel", "dcc", T::String).a("currentColorSet", "ccls", T::String)
        .a("uvSet", "uvst", T::Compound, 0, U::None, true)
        .a("uvSetName", "uvsn", T::String, 0, U::None, false, "uvSet")
        .c("uvSetPoints", "uvsp", T::Float2, {0, 0, 0, 0}, U::None, {{"uvSetPointsU", "uvspu"}, {"uvSetPointsV", "uvspv"}}, true, "uvSet")
        .a("uvSetTweakLocation", "uvtw", T::VectorArray, 0, U::None, false, "uvSet")
        .a("colorSet", "clst", T::Compound, 0, U::None, true)
        .a("colorName", "clsn", T::String, 0, U::None, false, "colorSet")
        .a("clamped", "clam", T::Bool, 0, U::None, false, "colorSet")
        .a("representation", "rprt", T::Enum, 3, U::None, false, "colorSet")
        .a("colorSetPoints", "clsp", T::Double4, 0, U::None, true, "colorSet");

    t.type("mesh", "controlPoint");
    // Point arrays are float3 data in internal units (centimetres) whatever the file's linear unit:
    // a metre scene's polyTweak moves its points by the centimetres written (Maya's own recorded
    // extrusion bounds on real metre scenes agree only so).
    t.c("vrts", "vt", T::Float3, {0, 0, 0, 0}, U::None, {{"vrtx", "vx"}, {"vrty", "vy"}, {"vrtz", "vz"}}, true)
        .c("pnts", "pt", T::Float3, {0, 0, 0, 0}, U::None, {{"pntx", "px"}, {"pnty", "py"}, {"pntz", "pz"}}, true)
        .c("edge", "ed", T::Long3, {0, 0, 0, 0}, U::None, {{"edg1", "e1"}, {"edg2", "e2"}, {"edgh", "eh"}}, true)
        .a("face", "fc", T::PolyFaces, 0, U::None, true)
        .c("uvpt", "uv", T::Float2, {0, 0, 0, 0}, U::None, {{"uvpx", "uvpx"}, {"uvpy", "uvpy"}}, true)
        .c("normals", "n", T::Float3, {0, 0, 0, 0}, U::None, {{"normalx", "nx"}, {"normaly", "ny"}, {"normalz", "nz"}}, true)
        .a("colors", "clr", T::Double4, 0, U::None, true).a("colorPerVertex", "cpvx", T::Compound)
        .a("inMesh", "i", T::Mesh).a("outMesh", "o", T::Mesh).a("cachedInMesh", "ci", T::Mesh)
        .a("worldMesh", "w", T::Mesh, 0, U::None, true)
        .a("outSmoothMesh", "osm", T::Mesh).a("smoothLevel", "lev", T::Int, 2)
        .a("displaySmoothMesh", "dsm", T::Enum).a("useSmoothPreviewForRender", "uspr", T::Bool, 1)
        .a("renderSmoothLevel", "rsl", T::Int, 1).a("vertexColorSource", "vcs", T::Enum)
        .a("backfaceCulling", "bck", T::Enum).a("vertexBackfaceCulling", "vbc", T::Bool)
        .a("edgeIdMap", "emap", T::Int32Array).a("faceIdMap", "fmap", T::Int32Array)
        .a("vertexIdMap", "vmap", T::Int32Array).a("pinData", "pd", T::Generic, 0, U::None, true)
        .a("holeFaceData", "hfd", T::Generic).a("creaseData", "cd", T::Generic)
        .a("creaseVertexData", "cvd", T::Generic).a("allowTopologyMod", "atm", T::Bool, 1)
        .a("keepBorder", "kb", T::Bool, 1).a("keepHardEdge", "khe", T::Bool)
        .a("continuity", "c", T::Double, 1).a("smoothUVs", "suv", T::Bool, 1)
        .a("propagateEdgeHardness", "peh", T::Bool).a("osdFvarBoundary", "ofb", T::Enum);

    t.type("nurbsSurface", "controlPoint");
    t.a("create", "cr", T::NurbsSurface).a("cached", "cc", T::NurbsSurface).a("local", "l", T::NurbsSurface)
        .a("worldSpace", "ws", T::NurbsSurface, 0, U::None, true).a("tweakSize", "ts", T::Int)
        .a("divisionsU", "dvu", T::Int).a("divisionsV", "dvv", T::Int)
        .a("curvePrecision", "cpr", T::Int, 4).a("curvePrecisionShaded", "cps", T::Int, 1)
        .a("simplifyMode", "smd", T::Enum).a("simplifyU", "smu", T::Int, 1).a("simplifyV", "smv", T::Int, 1)
        .a("dispCV", "dcv", T::Bool).a("dispEP", "dep", T::Bool).a("dispHull", "dh", T::Bool)
        .a("dispGeometry", "dg", T::Bool, 1).a("dispSF", "dsf", T::Bool).a("normalsDisplayScale", "ndt", T::Double, 1)
        .a("explicitTessellationAttributes", "eta", T::Bool).a("curvatureTolerance", "cvto", T::Enum, 2)
        .a("uDivisionsFactor", "nufa", T::Double, 1.5).a("vDivisionsFactor", "nvfa", T::Double, 1.5)
        .a("modeU", "mu", T::Enum, 3).a("modeV", "mv", T::Enum, 3).a("numberU", "nu", T::Int, 3)
        .a("numberV", "nv", T::Int, 3).a("useChordHeight", "uch", T::Bool).a("chordHeight", "ch", T::Double, 0.1)
        .a("useChordHeightRatio", "ucr", T::Bool, 1).a("chordHeightRatio", "chr", T::Double, 0.983)
        .a("objSpaceChordHeight", "uco", T::Bool, 1).a("useMinScreen", "uns", T::Bool)
        .a("minScreen", "mns", T::Double, 14).a("edgeSwap", "es", T::Bool).a("smoothEdge", "ues", T::Bool)
        .a("smoothEdgeRatio", "esr", T::Double, 0.99).a("gridDivisionPerSpanU", "gdsu", T::Int, 4)
        .a("gridDivisionPerSpanV", "gdsv", T::Int, 4).a("fixTextureWarp", "ftwp", T::Bool);

    t.type("curveShape", "controlPoint");
    t.type("nurbsCurve", "curveShape");
    t.a("create", "cr", T::NurbsCurve).a("cached", "cc", T::NurbsCurve).a("local", "l", T::NurbsCurve)
        .a("worldSpace", "ws", T::NurbsCurve, 0, U::None, true).a("tweakSize", "ts", T::Int)
        .a("dispCV", "dcv", T::Bool).a("dispEP", "dep", T::Bool).a("dispHull", "dh", T::Bool)
        .a("dispGeometry", "dg", T::Bool, 1).a("dispCurveEndPoints", "dce", T::Bool);

    t.type("locator", "shape");
    t.xyz("localPosition", "lp", T::Double3, 0, 0, 0, U::Distance).xyz("localScale", "los", T::Double3, 1, 1, 1, U::None);

    t.type("camera", "shape");
    t.a("renderable", "rnd", T::Bool, 1).a("focalLength", "fl", T::Double, 35)
        .c("cameraAperture", "cap", T::Double2, {1.41732, 0.94488, 0, 0}, U::None,
           {{"horizontalFilmAperture", "hfa"}, {"verticalFilmAperture", "vfa"}})
        .a("lensSqueezeRatio", "lsr", T::Double, 1).a("filmFit", "ff", T::Enum, 1)
        .a("filmFitOffset", "ffo", T::Double, 0)
        .c("filmOffset", "fio", T::Double2, {0, 0, 0, 0}, U::None, {{"horizontalFilmOffset", "hfo"}, {"verticalFilmOffset", "vfo"}})
        .a("overscan", "ovr", T::Double, 1).a("preScale", "psc", T::Double, 1).a("postScale", "ptsc", T::Double, 1)
        .a("filmTranslate", "ct", T::Double2).a("filmRollPivot", "rpv", T::Double2)
        .a("filmRollValue", "frv", T::Double, 0, U::Angle).a("filmRollOrder", "fro", T::Enum)
        .a("nearClipPlane", "ncp", T::Double, 0.1, U::Distance).a("farClipPlane", "fcp", T::Double, 10000, U::Distance)
        .a("orthographic", "o", T::Bool).a("orthographicWidth", "ow", T::Double, 10, U::Distance)
        .a("centerOfInterest", "coi", T::Double, 5, U::Distance).a("depthOfField", "dof", T::Bool)
        .a("focusDistance", "fd", T::Double, 5, U::Distance).a("fStop", "fs", T::Double, 5.6)
        .a("focusRegionScale", "frs", T::Double, 1).a("shutterAngle", "sa", T::Double, 144 * kDeg, U::Angle)
        .a("image", "img", T::Message).a("mask", "ma", T::Bool, 1).a("depth", "dep", T::Bool, 0)
        .a("depthType", "dptp", T::Enum, 1).a("depthName", "dn", T::String)
        .color("backgroundColor", "col", 0, 0, 0, "col")
        .a("imageName", "imn", T::String).a("cameraScale", "cs", T::Double, 1)
        .a("tumblePivot", "tp", T::Double3, 0, U::Distance).a("usePivotAsLocalSpace", "uplc", T::Bool)
        .a("homeCommand", "hc", T::String).a("bookmarks", "b", T::Message, 0, U::None, true)
        .a("locatorScale", "lls", T::Double, 1).a("displayFilmGate", "dfg", T::Bool)
        .a("displayResolution", "dr", T::Bool).a("displayGateMask", "dgm", T::Bool, 1)
        .a("stereoHorizontalImageTranslate", "hit", T::Double).a("imagePlane", "ip", T::Message, 0, U::None, true)
        .a("motionBlurOverride", "mbo", T::Enum).a("journalCommand", "jc", T::Bool);
}

void addLightTypes(Table& t) {
    t.type("light", "shape");
    t.color("color", "cl", 1, 1, 1, "c").a("intensity", "in", T::Float, 1)
        .color("shadowColor", "sc", 0, 0, 0, "sc").a("useRayTraceShadows", "urs", T::Bool, 1)
        .a("shadowRays", "shr", T::Int, 1).a("rayDepthLimit", "rdl", T::Int, 3)
        .a("centerOfIllumination", "col", T::Double, 5, U::Distance).a("locatorScale", "lls", T::Double, 1)
        .a("lightData", "ltd", T::Compound).a("physical", "phy", T::Bool, 1)
        .a("uiDrawType", "udt", T::Enum).a("infoBits", "ib", T::Int);
    t.type("renderLight", "light");
    t.type("ambientLight", "renderLight");
    t.a("ambientShade", "as", T::Float, 0.45).a("shadowRadius", "sr", T::Float, 0)
        .a("castSoftShadows", "cw", T::Bool);
    t.type("nonAmbientLightShapeNode", "renderLight");
    t.a("decayRate", "de", T::Enum, 0).a("emitDiffuse", "edi", T::Bool, 1).a("emitSpecular", "esp", T::Bool, 1);
    t.type("nonExtendedLightShapeNode", "nonAmbientLightShapeNode");
    t.a("useDepthMapShadows", "dms", T::Bool).a("dmapResolution", "dr", T::Int, 512)
        .a("dmapFilterSize", "fs", T::Int, 1).a("dmapBias", "db", T::Float, 0.001f)
        .a("useMidDistDmap", "md", T::Bool, 1).a("useDmapAutoFocus", "af", T::Bool, 1)
        .a("dmapFocus", "df", T::Double, 90 * kDeg, U::Angle).a("dmapWidthFocus", "dw", T::Double, 100)
        .a("useDmapAutoClipping", "uc", T::Bool, 1).a("dmapNearClipPlane", "nc", T::Double, 0.001, U::Distance)
        .a("dmapFarClipPlane", "fcp", T::Double, 10000, U::Distance).a("useOnlySingleDmap", "us", T::Bool, 1)
        .a("useXPlusDmap", "xp", T::Bool, 1).a("useXMinusDmap", "xn", T::Bool, 1)
        .a("useYPlusDmap", "yp", T::Bool, 1).a("useYMinusDmap", "yn", T::Bool, 1)
        .a("useZPlusDmap", "zp", T::Bool, 1).a("useZMinusDmap", "zn", T::Bool, 1)
        .a("reuseDmap", "du", T::Bool).a("writeDmap", "ws", T::Bool).a("dmapName", "smn", T::String)
        .a("dmapLightName", "ul", T::Bool, 1).a("dmapSceneName", "um", T::Bool).a("dmapFrameExt", "uf", T::Bool)
        .a("volumeShadowSamples", "nv", T::Int, 20).a("fogShadowIntensity", "fsi", T::Float, 1)
        .a("lightRadius", "lr", T::Double, 0, U::Distance).a("castSoftShadows", "cw", T::Bool)
        .a("receiveShadows", "gs", T::Bool, 1);
    t.type("pointLight", "nonExtendedLightShapeNode");
    t.a("fogType", "ft", T::Enum).a("fogRadius", "fr", T::Double, 1, U::Distance).a("fogIntensity", "fin", T::Double, 1);
    t.type("spotLight", "nonExtendedLightShapeNode");
    t.a("coneAngle", "ca", T::Double, 40 * kDeg, U::Angle).a("penumbraAngle", "pa", T::Double, 0, U::Angle)
        .a("dropoff", "dro", T::Double, 0).a("barnDoors", "bd", T::Bool)
        .a("leftBarnDoor", "lbd", T::Double, 20 * kDeg, U::Angle).a("rightBarnDoor", "rbd", T::Double, 20 * kDeg, U::Angle)
        .a("topBarnDoor", "tbd", T::Double, 20 * kDeg, U::Angle).a("bottomBarnDoor", "bbd", T::Double, 20 * kDeg, U::Angle)
        .a("useDecayRegions", "udr", T::Bool)
        .a("startDistance1", "sd1", T::Double, 1, U::Distance).a("endDistance1", "ed1", T::Double, 2, U::Distance)
        .a("startDistance2", "sd2", T::Double, 3, U::Distance).a("endDistance2", "ed2", T::Double, 6, U::Distance)
        .a("startDistance3", "sd3", T::Double, 8, U::Distance).a("endDistance3", "ed3", T::Double, 10, U::Distance)
        .a("fogSpread", "fsp", T::Double, 1).a("fogIntensity", "fin", T::Double, 1)
        .a("psIllumSamples", "pis", T::Int, 1);
    t.type("directionalLight", "nonExtendedLightShapeNode");
    t.a("useLightPosition", "up", T::Bool).a("lightAngle", "lang", T::Double, 0, U::Angle);
    t.type("areaLight", "nonExtendedLightShapeNode");
    t.a("normalize", "nrm", T::Bool, 1);
    t.type("volumeLight", "nonExtendedLightShapeNode");
    t.a("lightShape", "lis", T::Enum, 1).a("volumeLightDir", "vld", T::Enum).a("arc", "ac", T::Double, 360 * kDeg, U::Angle)
        .a("coneEndRadius", "cer", T::Double, 0).a("emitAmbient", "ema", T::Bool);
}

void addShadingTypes(Table& t) {
    t.type("shadingDependNode", "node");
    t.type("lambert", "shadingDependNode");
    t.color("color", "c", 0.5, 0.5, 0.5, "c").color("transparency", "it", 0, 0, 0, "it")
        .color("ambientColor", "ambc", 0, 0, 0, "ambc").color("incandescence", "ic", 0, 0, 0, "ic")
        .a("diffuse", "dc", T::Float, 0.8).a("translucence", "tc", T::Float, 0)
        .a("translucenceDepth", "trsd", T::Float, 0.5).a("translucenceFocus", "tcf", T::Float, 0.5)
        .xyz("normalCamera", "n", T::Float3, 0, 0, 0, U::None)
        .a("glowIntensity", "gi", T::Float, 0).a("hideSource", "hs", T::Bool)
        .a("refractions", "rfc", T::Bool).a("refractiveIndex", "rfi", T::Float, 1)
        .a("refractionLimit", "rdl", T::Int, 6).a("shadowAttenuation", "fakc", T::Float, 0.5)
        .a("lightAbsorbance", "absb", T::Float, 0).a("surfaceThickness", "thik", T::Float, 0)
        .a("chromaticAberration", "crab", T::Bool).a("matteOpacityMode", "mom", T::Enum, 2)
        .a("matteOpacity", "mog", T::Float, 1).a("materialAlphaGain", "maga", T::Float, 1)
        .a("opacityDepth", "opad", T::Float, 0).a("lightDataArray", "ltd", T::Compound, 0, U::None, true)
        .color("outColor", "oc", 0, 0, 0, "oc").color("outTransparency", "ot", 0, 0, 0, "ot")
        .color("outGlowColor", "ogc", 0, 0, 0, "ogc").color("outMatteOpacity", "omo", 0, 0, 0, "omo");
    t.type("reflect", "lambert");
    t.color("specularColor", "sc", 0.5, 0.5, 0.5, "s").a("reflectivity", "rfl", T::Float, 0.5)
        .color("reflectedColor", "rc", 0, 0, 0, "r").a("reflectionLimit", "fll", T::Int, 1)
        .a("reflectionSpecularity", "rsp", T::Float, 1);
    t.type("blinn", "reflect");
    t.a("eccentricity", "ec", T::Float, 0.3).a("specularRollOff", "sro", T::Float, 0.7)
        .a("reflectionRolloff", "rro", T::Bool, 1);
    t.type("phong", "reflect");
    t.a("cosinePower", "cp", T::Float, 20);
    t.type("phongE", "reflect");
    t.a("roughness", "rn", T::Float, 0.5).a("highlightSize", "hls", T::Float, 0.5)
        .color("whiteness", "wn", 0.5, 0.5, 0.5, "wn");
    t.type("anisotropic", "reflect");
    t.a("spreadX", "sprx", T::Float, 13).a("spreadY", "spry", T::Float, 3).a("roughness", "roug", T::Float, 0.7)
        .a("angle", "angl", T::Float, 0).a("fresnelRefractiveIndex", "frfi", T::Float, 6)
        .a("anisotropicReflectivity", "arfl", T::Bool, 1);
    t.type("surfaceShader", "shadingDependNode");
    t.color("outColor", "oc", 0, 0, 0, "oc").color("outTransparency", "ot", 0, 0, 0, "ot")
        .color("outGlowColor", "ogc", 0, 0, 0, "ogc").color("outMatteOpacity", "omo", 0, 0, 0, "omo")
        .a("materialAlphaGain", "maga", T::Float, 1);
    t.type("useBackground", "shadingDependNode");
    t.color("specularColor", "sc", 0.5, 0.5, 0.5, "s").a("reflectivity", "rfl", T::Float, 0.5)
        .a("reflectionLimit", "fll", T::Int, 2).a("shadowMask", "sm", T::Float, 1)
        .a("matteOpacityMode", "mom", T::Enum, 2).a("matteOpacity", "mog", T::Float, 1)
        .color("outColor", "oc", 0, 0, 0, "oc").color("outTransparency", "ot", 0, 0, 0, "ot");
    t.type("layeredShader", "shadingDependNode");
    t.a("inputs", "cs", T::Compound, 0, U::None, true)
        .color("color", "c", 0, 0, 0, "c", false, "inputs").color("transparency", "t", 1, 1, 1, "t", false, "inputs")
        .color("glowColor", "g", 0, 0, 0, "g", false, "inputs").a("compositingFlag", "cf", T::Enum)
        .color("outColor", "oc", 0, 0, 0, "oc").color("outTransparency", "ot", 0, 0, 0, "ot");

    t.type("entity", "node");
    t.type("objectSet", "entity");
    t.a("dagSetMembers", "dsm", T::Message, 0, U::None, true).a("dnSetMembers", "dnsm", T::Message, 0, U::None, true)
        .a("memberWireframeColor", "mwc", T::Int, -1).a("groupNodes", "gn", T::Message, 0, U::None, true)
        .a("partition", "pa", T::Message).a("usedBy", "ub", T::Message, 0, U::None, true)
        .a("annotation", "an", T::String).a("isLayer", "il", T::Bool).a("verticesOnlySet", "vo", T::Bool)
        .a("edgesOnlySet", "eo", T::Bool).a("facetsOnlySet", "fo", T::Bool).a("editPointsOnlySet", "eps", T::Bool)
        .a("renderableOnlySet", "ro", T::Bool);
    t.type("shadingEngine", "objectSet");
    t.xyz("surfaceShader", "ss", T::Float3, 0, 0, 0, U::None).xyz("volumeShader", "vs", T::Float3, 0, 0, 0, U::None)
        .a("displacementShader", "ds", T::Float).xyz("imageShader", "is", T::Float3, 0, 0, 0, U::None)
        .a("linkedLights", "ll", T::Message, 0, U::None, true).a("ignoredLights", "il", T::Message, 0, U::None, true);
    t.type("partition", "entity");
    t.a("sets", "st", T::Message, 0, U::None, true).a("partitionType", "pt", T::Int);
    t.type("lightLinker", "node");
    t.a("link", "lnk", T::Compound, 0, U::None, true)
        .a("light", "llnk", T::Message, 0, U::None, false, "link").a("object", "olnk", T::Message, 0, U::None, false, "link")
        .a("ignore", "ign", T::Compound, 0, U::None, true)
        .a("lightIgnored", "lli", T::Message, 0, U::None, false, "ignore").a("objectIgnored", "oli", T::Message, 0, U::None, false, "ignore")
        .a("shadowLink", "slnk", T::Compound, 0, U::None, true)
        .a("shadowLight", "sllk", T::Message, 0, U::None, false, "shadowLink").a("shadowObject", "solk", T::Message, 0, U::None, false, "shadowLink")
        .a("shadowIgnore", "sign", T::Compound, 0, U::None, true)
        .a("shadowLightIgnored", "slli", T::Message, 0, U::None, false, "shadowIgnore").a("shadowObjectIgnored", "soli", T::Message, 0, U::None, false, "shadowIgnore");
    t.type("lightList", "node");
    t.a("lights", "l", T::Message, 0, U::None, true);
    t.type("materialInfo", "node");
    t.a("shadingGroup", "sg", T::Message).a("material", "m", T::Message).a("texture", "t", T::Message, 0, U::None, true)
        .a("textureChannel", "tc", T::Message).a("textureFilter", "tf", T::Enum);
    t.type("samplerInfo", "shadingDependNode");
    t.xyz("pointCamera", "p", T::Float3, 0, 0, 0, U::None).xyz("pointObj", "po", T::Float3, 0, 0, 0, U::None)
        .xyz("pointWorld", "pw", T::Float3, 0, 0, 0, U::None).xyz("normalCamera", "n", T::Float3, 0, 0, 0, U::None)
        .c("uvCoord", "uv", T::Float2, {0, 0, 0, 0}, U::None, {{"uCoord", "u"}, {"vCoord", "v"}})
        .xyz("rayDirection", "r", T::Float3, 0, 0, 0, U::None).xyz("tangentUCamera", "tu", T::Float3, 0, 0, 0, U::None)
        .xyz("tangentVCamera", "tv", T::Float3, 0, 0, 0, U::None).a("matrixEyeToWorld", "e2w", T::Matrix)
        .a("pixelCenter", "pc", T::Float2).a("flippedNormal", "fn", T::Bool).a("facingRatio", "fr", T::Float);
    t.type("time", "node");
    t.a("outTime", "o", T::Double, 1, U::Time).a("enableTimewarp", "ewp", T::Bool).a("timewarpIn_Raw", "twir", T::Double, 0, U::Time);
    t.type("unitConversion", "node");
    t.a("input", "i", T::Generic).a("output", "o", T::Generic).a("conversionFactor", "cf", T::Double, 1);
}

void addRenderSettingTypes(Table& t) {
    t.type("renderQuality", "node");
    t.a("edgeAntiAliasing", "eaa", T::Enum, 3).a("shadingSamples", "ss", T::Int, 1)
        .a("maxShadingSamples", "mss", T::Int, 8).a("visibilitySamples", "mvs", T::Int, 1)
        .a("maxVisibilitySamples", "mvm", T::Int, 4).a("volumeSamples", "vs", T::Int, 1)
        .a("particleSamples", "pss", T::Int, 1).a("useMultiPixelFilter", "ufil", T::Bool, 0)
        .a("pixelFilterType", "pft", T::Enum, 2).a("pixelFilterWidthX", "pfwx", T::Float, 2.2)
        .a("pixelFilterWidthY", "pfwy", T::Float, 2.2).a("plugInFilterWeight", "pifw", T::Float, 1)
        .a("redThreshold", "rct", T::Float, 0.4).a("greenThreshold", "gct", T::Float, 0.3)
        .a("blueThreshold", "bct", T::Float, 0.6).a("coverageThreshold", "cct", T::Float, 0.125)
        .a("enableRaytracing", "ert", T::Bool, 0).a("reflections", "rfl", T::Int, 1)
        .a("refractions", "rfr", T::Int, 6).a("shadows", "sl", T::Int, 2).a("rayTraceBias", "rtb", T::Float, 0)
        .a("renderSample", "rsdn", T::Bool, 0);
    t.type("renderGlobals", "node");
    t.a("currentRenderer", "ren", T::String).a("animation", "an", T::Bool, 0).a("animationRange", "ar", T::Enum, 1)
        .a("startFrame", "fs", T::Double, 1, U::Time).a("endFrame", "ef", T::Double, 1, U::Time)
        .a("byFrameStep", "bfs", T::Double, 1, U::Time).a("modifyExtension", "me", T::Bool, 0)
        .a("startExtension", "se", T::Double, 1).a("byExtension", "be", T::Double, 1)
        .a("extensionPadding", "ep", T::Int, 1).a("imageFormat", "outf", T::Enum, 7)
        .a("imfPluginKey", "imfkey", T::String).a("imageFilePrefix", "ifp", T::String)
        .a("outFormatControl", "ofc", T::Enum, 0).a("outFormatExt", "oft", T::String)
        .a("putFrameBeforeExt", "pff", T::Bool, 0).a("periodInExt", "peie", T::Enum, 1)
        .a("useMayaFileName", "umfn", T::Bool, 1).a("useFrameExt", "ufe", T::Bool, 0)
        .a("fieldExtControl", "fec", T::Enum, 0).a("gammaCorrection", "gama", T::Float, 1)
        .a("ignoreFilmGate", "ifg", T::Bool, 1).a("clipFinalShadedColor", "clip", T::Bool, 1)
        .a("jitterFinalColor", "jfc", T::Bool, 1).a("composite", "comp", T::Bool, 0)
        .a("compositeThreshold", "cth", T::Float, 0).a("enableDepthMaps", "edm", T::Bool, 1)
        .a("enableDefaultLight", "edl", T::Bool, 1).a("shadowsObeyLightLinking", "soll", T::Bool, 1)
        .a("shadowsObeyShadowLinking", "sosl", T::Bool, 0).a("raysSeeBackground", "rsb", T::Bool, 1)
        .a("recursionDepth", "rd", T::Int, 2).a("leafPrimitives", "lp", T::Int, 200)
        .a("subdivisionPower", "sp", T::Float, 0.25).a("maximumMemory", "mm", T::Int, 48)
        .a("numCpusToUse", "npu", T::Int, 0).a("forceTileSize", "frts", T::Bool, 0)
        .a("tileWidth", "tlwd", T::Int, 64).a("tileHeight", "tlht", T::Int, 64)
        .a("useFileCache", "uf", T::Bool, 1).a("optimizeInstances", "oi", T::Bool, 1)
        .a("reuseTessellations", "rut", T::Bool, 1).a("useDisplacementBoundingBox", "udbx", T::Bool, 1)
        .a("shadowPass", "shp", T::Bool, 0).a("motionBlur", "mb", T::Bool, 0).a("motionBlurType", "mbt", T::Enum, 1)
        .a("motionBlurByFrame", "mbf", T::Float, 1).a("blurLength", "bll", T::Float, 1)
        .a("blurSharpness", "bls", T::Float, 1).a("smoothValue", "smv", T::Int, 2).a("smoothColor", "smc", T::Bool, 0)
        .a("keepMotionVector", "kmv", T::Bool, 0).a("useBlur2DMemoryCap", "ubc", T::Bool, 1)
        .a("blur2DMemoryCap", "mbc", T::Float, 200).a("matteOpacityUsesTransparency", "mot", T::Bool, 1)
        .a("applyFogInPost", "afp", T::Bool, 0).a("postFogBlur", "pfb", T::Int, 1)
        .a("left", "left", T::Int, 0).a("rght", "rght", T::Int, 0).a("bot", "bot", T::Int, 0).a("top", "top", T::Int, 0)
        .a("useRenderRegion", "urr", T::Bool, 0).a("preMel", "pram", T::String).a("postMel", "poam", T::String)
        .a("preRenderMel", "prm", T::String).a("postRenderMel", "pom", T::String).a("renderAll", "ra", T::Bool, 1)
        .a("quality", "qual", T::Message).a("resolution", "res", T::Message)
        .a("useTextureCache", "utc", T::Bool, 0);
    t.type("resolution", "node");
    t.a("width", "w", T::Int, 640).a("height", "h", T::Int, 480).a("deviceAspectRatio", "dar", T::Float, 1.333)
        .a("pixelAspect", "pa", T::Float, 0).a("aspectLock", "al", T::Bool, 0)
        .a("lockDeviceAspectRatio", "ldar", T::Bool, 0).a("dotsPerInch", "dpi", T::Float, 72)
        .a("fields", "fld", T::Enum, 0).a("oddFieldFirst", "off", T::Bool, 1).a("zerothScanline", "zsl", T::Enum, 0)
        .a("imageSizeUnits", "isu", T::Enum, 0).a("pixelDensityUnits", "pdu", T::Enum, 0);
}

void addAnimationTypes(Table& t) {
    // Key values are stored as written (in the file's units for TL/TA/UL/UA curves); the
    // evaluator converts a curve's output by its type.
    t.type("animCurve", "node");
    t.c("keyTimeValue", "ktv", T::Double2, {0, 0, 0, 0}, U::None, {{"keyTime", "kt"}, {"keyValue", "kv"}}, true)
        .a("keyTanLocked", "ktl", T::Bool, 1, U::None, true).a("keyWeightLocked", "kwl", T::Bool, 1, U::None, true)
        .a("keyTanInType", "kit", T::Enum, 0, U::None, true).a("keyTanOutType", "kot", T::Enum, 0, U::None, true)
        .a("keyTanInX", "kix", T::Double, 1, U::None, true).a("keyTanInY", "kiy", T::Double, 0, U::None, true)
        .a("keyTanOutX", "kox", T::Double, 1, U::None, true).a("keyTanOutY", "koy", T::Double, 0, U::None, true)
        .a("keyBreakdown", "kbd", T::Bool, 0, U::None, true).a("keyTickDrawSpecial", "ktds", T::Bool, 0, U::None, true)
        .a("tangentType", "tan", T::Enum, 18).a("weightedTangents", "wgt", T::Bool, 1)
        .a("inTangentType", "itt", T::Enum, 0).a("outTangentType", "ott", T::Enum, 0)
        .a("preInfinity", "pre", T::Enum, 0).a("postInfinity", "pst", T::Enum, 0)
        .a("useCurveColor", "ucc", T::Bool).a("stipplePattern", "ssp", T::Int).a("rotationInterpolation", "roti", T::Enum)
        .a("input", "i", T::Double).a("output", "o", T::Double).a("apply", "ap", T::Double);
    for (const char* name : {"animCurveTL", "animCurveTA", "animCurveTU", "animCurveTT", "animCurveUL",
                             "animCurveUA", "animCurveUU", "animCurveUT"})
        t.type(name, "animCurve");
}

void addHistoryTypes(Table& t) {
    t.type("polyBase", "node");
    t.a("output", "out", T::Mesh).a("cachedInMesh", "cin", T::Mesh);
    t.type("polyCreator", "polyBase");
    t.type("polyPrimitive", "polyCreator");
    t.xyz("axis", "ax", T::Double3, 0, 1, 0, U::None).a("paramWarn", "pw", T::Bool, 1)
        .a("uvSetName", "uvs", T::String).a("createUVs", "cuv", T::Int, 1);
    t.type("polyCube", "polyPrimitive");
    t.a("width", "w", T::Double, 1, U::Distance).a("height", "h", T::Double, 1, U::Distance)
        .a("depth", "d", T::Double, 1, U::Distance).a("subdivisionsWidth", "sw", T::Int, 1)
        .a("subdivisionsHeight", "sh", T::Int, 1).a("subdivisionsDepth", "sd", T::Int, 1);
    t.type("polySphere", "polyPrimitive");
    t.a("radius", "r", T::Double, 1, U::Distance).a("subdivisionsAxis", "sa", T::Int, 20)
        .a("subdivisionsHeight", "sh", T::Int, 20);
    t.type("polyPlane", "polyPrimitive");
    t.a("width", "w", T::Double, 1, U::Distance).a("height", "h", T::Double, 1, U::Distance)
        .a("subdivisionsWidth", "sw", T::Int, 10).a("subdivisionsHeight", "sh", T::Int, 10);
    t.type("polyCylinder", "polyPrimitive");
    t.a("radius", "r", T::Double, 1, U::Distance).a("height", "h", T::Double, 2, U::Distance)
        .a("subdivisionsAxis", "sa", T::Int, 20).a("subdivisionsHeight", "sh", T::Int, 1)
        .a("subdivisionsCaps", "sc", T::Int, 1).a("roundCap", "rcp", T::Bool, 0);
    t.type("polyCone", "polyPrimitive");
    t.a("radius", "r", T::Double, 1, U::Distance).a("height", "h", T::Double, 2, U::Distance)
        .a("subdivisionsAxis", "sa", T::Int, 20).a("subdivisionsHeight", "sh", T::Int, 1)
        .a("subdivisionsCap", "sc", T::Int, 0).a("roundCap", "rcp", T::Bool, 0);
    t.type("polyTorus", "polyPrimitive");
    t.a("radius", "r", T::Double, 1, U::Distance).a("sectionRadius", "sr", T::Double, 0.5, U::Distance)
        .a("twist", "tw", T::Double, 0, U::Angle).a("subdivisionsAxis", "sa", T::Int, 20)
        .a("subdivisionsHeight", "sh", T::Int, 20);
    t.type("polyPlatonicSolid", "polyPrimitive");
    t.a("radius", "r", T::Double, 1, U::Distance).a("sideLength", "l", T::Double, 0.7137, U::Distance)
        .a("solidType", "st", T::Enum, 0);
    t.type("polyModifier", "polyBase");
    t.a("inputPolymesh", "ip", T::Mesh).a("inputComponents", "ics", T::ComponentList);
    t.type("polyTweak", "polyModifier");
    t.c("tweak", "tk", T::Float3, {0, 0, 0, 0}, U::None, {{"tweakX", "tx"}, {"tweakY", "ty"}, {"tweakZ", "tz"}}, true);
    // polyExtrudeFace and the polyMove* / polyModifierWorld attributes it inherits.
    t.type("polyModifierWorld", "polyModifier");
    t.a("inputMatrix", "ix", T::Matrix).a("worldSpace", "ws", T::Bool, 0).a("manipMatrix", "mp", T::Matrix);
    t.type("polyMoveVertex", "polyModifierWorld");
    t.xyz("translate", "t", T::Double3, 0, 0, 0, U::Distance).xyz("rotate", "r", T::Double3, 0, 0, 0, U::Angle)
        .xyz("scale", "s", T::Double3, 1, 1, 1, U::None)
        .c("pivot", "pvt", T::Float3, {0, 0, 0, 0}, U::Distance, {{"pivotX", "pvx"}, {"pivotY", "pvy"}, {"pivotZ", "pvz"}})
        .a("random", "ran", T::Double, 0).xyz("localTranslate", "lt", T::Double3, 0, 0, 0, U::Distance)
        .xyz("localDirection", "ld", T::Double3, 1, 0, 0, U::Distance);
    t.type("polyMoveEdge", "polyMoveVertex");
    t.xyz("localRotate", "lr", T::Double3, 0, 0, 0, U::Angle).xyz("localScale", "ls", T::Double3, 1, 1, 1, U::None)
        .a("localCenter", "lc", T::Enum, 0);
    t.type("polyMoveFace", "polyMoveEdge");
    t.a("offset", "off", T::Double, 0).a("attraction", "att", T::Double, 0).a("weight", "w", T::Double, 0)
        .xyz("gravity", "g", T::Double3, 0, -1, 0, U::Distance).xyz("magnet", "m", T::Double3, 0, 0, 0, U::Distance);
    // What polyExtrudeFace and polyExtrudeEdge both add (Maya gives them no common type for it).
    auto extrusionAttrs = [&t] {
        t.a("keepFacesTogether", "kft", T::Bool, 1).a("divisions", "dv", T::Int, 1).a("twist", "twt", T::Double, 0, U::Angle)
            .a("taper", "tp", T::Double, 1).a("thickness", "tk", T::Double, 0, U::Distance)
            .a("smoothingAngle", "sma", T::Double, 0.5235987755982988, U::Angle)
            .c("taperCurve", "c", T::Float3, {0, 1, 1, 0}, U::None,
               {{"taperCurve_Position", "cp"}, {"taperCurve_FloatValue", "cfv"}, {"taperCurve_Interp", "ci"}}, true)
            .c("compBoundingBoxMin", "cbn", T::Double3, {0, 0, 0, 0}, U::Distance,
               {{"compBoundingBoxMinX", "cnx"}, {"compBoundingBoxMinY", "cny"}, {"compBoundingBoxMinZ", "cnz"}})
            .c("compBoundingBoxMax", "cbx", T::Double3, {1, 1, 1, 0}, U::Distance,
               {{"compBoundingBoxMaxX", "cxx"}, {"compBoundingBoxMaxY", "cxy"}, {"compBoundingBoxMaxZ", "cxz"}});
    };
    t.type("polyExtrudeFace", "polyMoveFace");
    extrusionAttrs();
    t.a("reverseAllFaces", "raf", T::Bool, 0);
    t.type("polyExtrudeEdge", "polyMoveEdge");
    extrusionAttrs();
    t.a("offset", "off", T::Double, 0);
    t.type("polyBevel", "polyModifierWorld");
    t.a("offset", "o", T::Double, 0.2).a("offsetAsFraction", "oaf", T::Bool, 0).a("segments", "sg", T::Int, 1)
        .a("roundness", "ro", T::Double, 0.5).a("smoothingAngle", "sa", T::Double, 0.5235987755982988, U::Angle)
        .a("fraction", "f", T::Double, 0.2).a("autoFit", "af", T::Bool, 1);
    t.type("polyBevel3", "polyModifierWorld");
    t.a("offset", "o", T::Double, 0.2).a("offsetAsFraction", "oaf", T::Bool, 1).a("segments", "sg", T::Int, 1)
        .a("fraction", "f", T::Double, 0.5).a("depth", "d", T::Double, 1).a("chamfer", "c", T::Bool, 1)
        .a("smoothingAngle", "sa", T::Double, 0.5235987755982988, U::Angle).a("mitering", "mm", T::Enum, 0)
        .a("autoFit", "af", T::Bool, 1);
    t.type("polySplitRing", "polyModifierWorld");
    t.a("weight", "wt", T::Double, 0.5).a("direction", "dr", T::Bool, 1).a("rootEdge", "re", T::Int, -1)
        .a("splitType", "stp", T::Enum, 0).a("divisions", "div", T::Int, 2)
        .a("smoothingAngle", "sma", T::Double, 0.5235987755982988, U::Angle).a("fixQuads", "fq", T::Bool, 0)
        .a("insertWithEdgeFlow", "iwe", T::Bool, 0)
        .c("tweak", "tk", T::Float3, {0, 0, 0, 0}, U::None, {{"tweakX", "tx"}, {"tweakY", "ty"}, {"tweakZ", "tz"}}, true);
    t.type("polySplit", "polyModifier");
    t.a("edge", "e", T::Float, 0, U::None, true).a("desc", "d", T::Int, 0, U::None, true)
        .c("vertices", "v", T::Float3, {0, 0, 0, 0}, U::Distance, {{"vtxx", "vx"}, {"vtxy", "vy"}, {"vtxz", "vz"}}, true)
        .a("subdivision", "s", T::Int, 1).a("smoothingAngle", "sma", T::Double, 0, U::Angle)
        .a("clean2Verts", "c2v", T::Bool, 0).a("maya70", "m70", T::Bool, 0).a("maya2015", "m2015", T::Bool, 0)
        .a("insertWithEdgeFlow", "iwe", T::Bool, 0).a("adjustEdgeFlow", "aef", T::Float, 1).a("detachEdges", "de", T::Bool, 0);
    t.type("polyMergeVert", "polyModifierWorld");
    t.a("distance", "d", T::Double, 0, U::Distance).a("alwaysMergeTwoVertices", "am", T::Bool, 0)
        .a("mergeToComponents", "mtc", T::ComponentList)
        .c("tweak", "tk", T::Float3, {0, 0, 0, 0}, U::None, {{"tweakX", "tx"}, {"tweakY", "ty"}, {"tweakZ", "tz"}}, true);
    t.type("polyTweakUV", "polyModifier");
    t.a("uvTweak", "uvtk", T::Float2, 0, U::None, true).a("uvSetName", "uvs", T::String);
    // Evaluated by mesh_eval: polyTriangulate and polySoftEdge change the mesh; the others pass
    // the geometry through (their UV or normal edits are reported as not applied).
    t.type("polyTriangulate", "polyModifier");
    t.type("polySoftEdge", "polyModifier");
    t.a("angle", "a", T::Double, 0.5235987755982988, U::Angle);
    t.type("polyNormal", "polyModifier");
    t.a("normalMode", "nm", T::Enum, 0).a("userNormalMode", "unm", T::Bool, 0);
    t.type("polyNormalPerVertex", "polyModifier");
    t.type("polyModifierUV", "polyModifier");
    t.a("uvSetName", "uvs", T::String);
    for (const char* uvOnly : {"polyAutoProj", "polyPlanarProj", "polyCylProj", "polySphProj", "polyProjection",
                               "polyMapCut", "polyMapSew", "polyMapSewMove", "polyMapDel", "polyNormalizeUV",
                               "polyLayoutUV", "polyFlipUV", "polyMoveUV", "polyCopyUV", "polyUVRectangle",
                               "polyOptUvs", "polyMergeUV"})
        t.type(uvOnly, "polyModifierUV");
    for (const char* unfold : {"Unfold3DUnfold", "Unfold3DOptimize"}) {
        t.type(unfold, "node");
        t.a("inMesh", "im", T::Mesh).a("outMesh", "om", T::Mesh);
    }
    t.type("createUVSet", "node");
    t.a("uvSetName", "uvs", T::String).a("inputGeometry", "ig", T::Generic).a("outputGeometry", "og", T::Generic);
    t.type("deleteComponent", "node");
    t.a("deleteComponents", "dc", T::ComponentList).a("inputGeometry", "ig", T::Generic)
        .a("outputGeometry", "og", T::Generic);
    t.type("groupParts", "node");
    t.a("inputComponents", "ic", T::ComponentList).a("groupId", "gi", T::Int)
        .a("inputGeometry", "ig", T::Generic).a("outputGeometry", "og", T::Generic);
    t.type("groupId", "node");
    t.a("groupId", "id", T::Int).a("isHistoricallyInteresting", "ihi", T::Int, 2);
    t.type("transformGeometry", "node");
    t.a("transform", "txf", T::Matrix).a("inputGeometry", "ig", T::Generic).a("outputGeometry", "og", T::Generic)
        .a("invertTransform", "itf", T::Bool, 0).a("freezeNormals", "fn", T::Enum, 0);

    t.type("abstractBaseCreate", "node");
    t.type("primitive", "abstractBaseCreate");
    t.xyz("pivot", "p", T::Double3, 0, 0, 0, U::Distance).xyz("axis", "ax", T::Double3, 1, 0, 0, U::None)
        .a("radius", "r", T::Double, 1, U::Distance).a("degree", "d", T::Enum, 3)
        .a("useTolerance", "ut", T::Bool, 0).a("tolerance", "tol", T::Double, 0.01, U::Distance)
        .a("outputSurface", "os", T::NurbsSurface);
    t.type("revolvedPrimitive", "primitive");
    t.a("startSweep", "ssw", T::Double, 0, U::Angle).a("endSweep", "esw", T::Double, 360 * kDeg, U::Angle)
        .a("sections", "s", T::Int, 8).a("spans", "nsp", T::Int, 1).a("heightRatio", "hr", T::Double, 2);
    // A sphere Maya creates with default settings is written without `nsp`: its default is 4.
    t.type("makeNurbSphere", "revolvedPrimitive");
    t.a("spans", "nsp", T::Int, 4);
    t.type("makeNurbCylinder", "revolvedPrimitive");
    t.type("makeNurbCone", "revolvedPrimitive");
    t.a("useOldInitBehaviour", "oib", T::Bool, 0);
    t.type("makeNurbTorus", "revolvedPrimitive");
    t.a("minorSweep", "msw", T::Double, 360 * kDeg, U::Angle).a("spans", "nsp", T::Int, 4)
        .a("heightRatio", "hr", T::Double, 0.5);
    t.type("makeNurbPlane", "primitive");
    t.a("width", "w", T::Double, 1, U::Distance).a("lengthRatio", "lr", T::Double, 1)
        .a("patchesU", "u", T::Int, 1).a("patchesV", "v", T::Int, 1);
    t.type("makeNurbCube", "primitive");
    t.a("width", "w", T::Double, 1, U::Distance).a("lengthRatio", "lr", T::Double, 1)
        .a("heightRatio", "hr", T::Double, 1).a("patchesU", "u", T::Int, 1).a("patchesV", "v", T::Int, 1)
        .a("outputSurface", "os", T::NurbsSurface, 0, U::None, true);
    t.type("makeNurbCircle", "abstractBaseCreate");
    t.xyz("center", "c", T::Double3, 0, 0, 0, U::Distance).xyz("normal", "nr", T::Double3, 0, 0, 1, U::None)
        .a("radius", "r", T::Double, 1, U::Distance).a("sweep", "sw", T::Double, 360 * kDeg, U::Angle)
        .a("degree", "d", T::Enum, 3).a("sections", "s", T::Int, 8).a("outputCurve", "oc", T::NurbsCurve);
    // NURBS construction history evaluated by nurbs_eval (geom/nurbs_ops.h).
    t.type("revolve", "abstractBaseCreate");
    t.xyz("pivot", "p", T::Double3, 0, 0, 0, U::Distance).xyz("axis", "ax", T::Double3, 1, 0, 0, U::None)
        .a("startSweep", "ssw", T::Double, 0, U::Angle).a("endSweep", "esw", T::Double, 360 * kDeg, U::Angle)
        .a("sections", "s", T::Int, 8).a("degree", "d", T::Enum, 3).a("useTolerance", "ut", T::Bool, 0)
        .a("tolerance", "tol", T::Double, 0.01, U::Distance).a("axisChoice", "ach", T::Enum, 0)
        .a("computePivotAndAxis", "cpa", T::Enum, 0).a("autoCorrectNormal", "acn", T::Bool, 0)
        .a("bridge", "br", T::Bool, 0).a("radius", "r", T::Double, 1, U::Distance)
        .a("inputCurve", "ic", T::NurbsCurve).a("outputSurface", "os", T::NurbsSurface);
    t.type("detachSurface", "abstractBaseCreate");
    t.a("inputSurface", "is", T::NurbsSurface).a("parameter", "p", T::Double, 0, U::None, true)
        .a("keep", "k", T::Bool, 1, U::None, true).a("direction", "d", T::Int, 1)
        .a("outputSurface", "os", T::NurbsSurface, 0, U::None, true);
    t.type("insertKnotSurface", "abstractBaseCreate");
    t.a("inputSurface", "is", T::NurbsSurface).a("parameter", "p", T::Double, 0, U::None, true)
        .a("numberOfKnots", "nk", T::Int, 1, U::None, true).a("direction", "d", T::Int, 1)
        .a("insertBetween", "ib", T::Bool, 0).a("addKnots", "add", T::Bool, 1).a("outputSurface", "os", T::NurbsSurface);
    t.type("rebuildSurface", "abstractBaseCreate");
    t.a("inputSurface", "is", T::NurbsSurface).a("rebuildType", "rt", T::Enum, 0).a("direction", "dir", T::Enum, 2)
        .a("spansU", "su", T::Int, 4).a("spansV", "sv", T::Int, 4).a("degreeU", "du", T::Enum, 3).a("degreeV", "dv", T::Enum, 3)
        .a("keepRange", "kr", T::Enum, 1).a("keepControlPoints", "kc", T::Bool, 0).a("endKnots", "end", T::Enum, 0)
        .a("keepCorners", "kcp", T::Bool, 0).a("outputSurface", "os", T::NurbsSurface);
    t.type("extrude", "abstractBaseCreate");
    t.a("profile", "pr", T::NurbsCurve).a("path", "pt", T::NurbsCurve).a("extrudeType", "et", T::Enum, 2)
        .a("fixedPath", "fpt", T::Bool, 0).a("useComponentPivot", "ucp", T::Enum, 0).a("useProfileNormal", "upn", T::Bool, 0)
        .xyz("direction", "d", T::Double3, 0, 1, 0, U::Distance).a("length", "l", T::Double, 1, U::Distance)
        .xyz("pivot", "p", T::Double3, 0, 0, 0, U::Distance).a("rotation", "ro", T::Double, 0, U::Angle)
        .a("scale", "sc", T::Double, 1).a("degreeAlongLength", "dl", T::Int, 1)
        .a("reverseSurfaceIfPathReversed", "rsp", T::Bool, 0).a("subCurveSubSurface", "scs", T::Bool, 0)
        .a("outputSurface", "os", T::NurbsSurface);
    t.type("loft", "abstractBaseCreate");
    t.a("inputCurve", "ic", T::NurbsCurve, 0, U::None, true).a("uniform", "u", T::Bool, 0).a("close", "c", T::Bool, 0)
        .a("degree", "d", T::Enum, 3).a("reverseSurfaceNormals", "rsn", T::Bool, 0).a("autoReverse", "ar", T::Bool, 1)
        .a("sectionSpans", "ss", T::Int, 1).a("reverse", "r", T::Bool, 0, U::None, true)
        .a("createCusp", "cc", T::Bool, 0, U::None, true).a("outputSurface", "os", T::NurbsSurface);
    t.type("parentTessellate", "node");
    t.a("format", "f", T::Enum, 1).a("polygonType", "pt", T::Enum, 0).a("polygonCount", "pc", T::Int, 200)
        .a("uType", "ut", T::Enum, 3).a("vType", "vt", T::Enum, 3).a("uNumber", "un", T::Int, 3)
        .a("vNumber", "vn", T::Int, 3).a("useChordHeight", "uch", T::Bool, 0)
        .a("chordHeight", "cht", T::Double, 0.1, U::Distance).a("useChordHeightRatio", "ucr", T::Bool, 1)
        .a("chordHeightRatio", "chr", T::Double, 0.983).a("delta", "d", T::Double, 0.1, U::Distance)
        .a("edgeSwap", "es", T::Bool, 0).a("fractionalTolerance", "ft", T::Double, 0.01)
        .a("minEdgeLength", "mel", T::Double, 0.001, U::Distance).a("matchNormalDir", "mnd", T::Bool, 0)
        .a("normalizeTrimmedUVRange", "ntr", T::Bool, 1).a("outputPolygon", "op", T::Mesh);
    t.type("nurbsTessellate", "parentTessellate");
    t.a("inputSurface", "is", T::NurbsSurface).a("explicitTessellationAttributes", "eta", T::Bool, 1)
        .a("curvatureTolerance", "cvt", T::Enum, 2).a("uDivisionsFactor", "nuf", T::Double, 1.5)
        .a("vDivisionsFactor", "nvf", T::Double, 1.5).a("smoothEdge", "ues", T::Bool, 0)
        .a("smoothEdgeRatio", "esr", T::Double, 0.99);
}

void addMiscTypes(Table& t) {
    t.type("script", "node");
    t.a("before", "b", T::String).a("after", "a", T::String).a("scriptType", "st", T::Enum)
        .a("sourceType", "stp", T::Enum);
    t.type("expression", "node");
    t.a("expression", "e", T::String).a("input", "in", T::Double, 0, U::None, true)
        .a("output", "out", T::Double, 0, U::None, true).a("time", "tim", T::Double, 0, U::Time)
        .a("frame", "frm", T::Double).a("animated", "ani", T::Enum, 0).a("objectMsg", "obm", T::Message);
    t.type("displayLayer", "node");
    t.a("displayType", "dt", T::Enum).a("levelOfDetail", "lod", T::Enum).a("shading", "s", T::Bool, 1)
        .a("texturing", "t", T::Bool, 1).a("playback", "p", T::Bool, 1).a("enabled", "e", T::Bool, 1)
        .a("visibility", "v", T::Bool, 1).a("hideOnPlayback", "hpb", T::Bool).a("color", "c", T::Int)
        .a("displayOrder", "do", T::Int).a("drawInfo", "di", T::Compound).a("identification", "id", T::Int);
    t.type("displayLayerManager", "node");
    t.a("currentDisplayLayer", "cdl", T::Int).a("displayLayerId", "dli", T::Int, 0, U::None, true);
    t.type("renderLayer", "node");
    t.a("renderable", "rndr", T::Bool, 1).a("global", "g", T::Bool).a("identification", "id", T::Int);
    t.type("renderLayerManager", "node");
    t.a("currentRenderLayer", "crl", T::Int).a("renderLayerId", "rlmi", T::Int, 0, U::None, true);
    t.type("place2dTexture", "node");
    t.c("coverage", "c", T::Float2, {1, 1, 0, 0}, U::None, {{"coverageU", "cu"}, {"coverageV", "cv"}})
        .c("translateFrame", "tf", T::Float2, {0, 0, 0, 0}, U::None, {{"translateFrameU", "tfu"}, {"translateFrameV", "tfv"}})
        .a("rotateFrame", "rf", T::Double, 0, U::Angle).a("mirrorU", "mu", T::Bool).a("mirrorV", "mv", T::Bool)
        .a("wrapU", "wu", T::Bool, 1).a("wrapV", "wv", T::Bool, 1).a("stagger", "s", T::Bool)
        .c("repeatUV", "re", T::Float2, {1, 1, 0, 0}, U::None, {{"repeatU", "reu"}, {"repeatV", "rev"}})
        .c("offset", "of", T::Float2, {0, 0, 0, 0}, U::None, {{"offsetU", "ofu"}, {"offsetV", "ofv"}})
        .a("rotateUV", "r", T::Double, 0, U::Angle)
        .c("noiseUV", "n", T::Float2, {0, 0, 0, 0}, U::None, {{"noiseU", "nu"}, {"noiseV", "nv"}})
        .a("fast", "fa", T::Bool)
        .c("uvCoord", "uv", T::Float2, {0, 0, 0, 0}, U::None, {{"uCoord", "u"}, {"vCoord", "v"}})
        .c("outUV", "o", T::Float2, {0, 0, 0, 0}, U::None, {{"outU", "ou"}, {"outV", "ov"}})
        .c("outUvFilterSize", "ofs", T::Float2, {0, 0, 0, 0}, U::None, {{"outUvFilterSizeX", "ofsx"}, {"outUvFilterSizeY", "ofsy"}});
    t.type("place3dTexture", "transform");
    t.type("texture2d", "shadingDependNode");
    t.c("uvCoord", "uv", T::Float2, {0, 0, 0, 0}, U::None, {{"uCoord", "u"}, {"vCoord", "v"}})
        .c("uvFilterSize", "fs", T::Float2, {0, 0, 0, 0}, U::None, {{"uvFilterSizeX", "fsx"}, {"uvFilterSizeY", "fsy"}})
        .color("defaultColor", "dc", 0.5, 0.5, 0.5, "dc").color("colorGain", "cg", 1, 1, 1, "cg")
        .color("colorOffset", "co", 0, 0, 0, "co").a("alphaGain", "ag", T::Float, 1).a("alphaOffset", "ao", T::Float, 0)
        .a("alphaIsLuminance", "ail", T::Bool).a("invert", "i", T::Bool).a("filter", "f", T::Float, 1)
        .a("filterOffset", "fo", T::Float, 0).color("outColor", "oc", 0, 0, 0, "oc").a("outAlpha", "oa", T::Float, 0);
    t.type("file", "texture2d");
    t.a("fileTextureName", "ftn", T::String).a("filterType", "ft", T::Enum, 3).a("filterWidth", "fw", T::Float, 0.707)
        .a("useCache", "uca", T::Bool).a("useFrameExtension", "ufe", T::Bool).a("frameExtension", "fe", T::Int, 1)
        .a("frameOffset", "io", T::Int, 0).a("preFilter", "pf", T::Bool).a("preFilterRadius", "pfr", T::Float, 2)
        .a("blurPixelation", "blp", T::Bool, 1).a("disableFileLoad", "dfl", T::Bool)
        .a("colorSpace", "cs", T::String).a("fileTextureNamePattern", "ftnp", T::String);
    t.type("checker", "texture2d");
    t.color("color1", "c1", 1, 1, 1, "c1").color("color2", "c2", 0, 0, 0, "c2").a("contrast", "ct", T::Float, 1);
    t.type("ramp", "texture2d");
    t.a("type", "t", T::Enum, 0).a("interpolation", "in", T::Enum, 1)
        .a("colorEntryList", "cel", T::Compound, 0, U::None, true)
        .a("position", "ep", T::Float, 0, U::None, false, "colorEntryList")
        .color("color", "ec", 0, 0, 0, "ec", false, "colorEntryList")
        .a("uWave", "uw", T::Float).a("vWave", "vw", T::Float).a("noise", "n", T::Float)
        .a("noiseFreq", "nf", T::Float, 0.5);
    t.type("bump2d", "shadingDependNode");
    t.a("bumpValue", "bv", T::Float).a("bumpDepth", "bd", T::Float, 1).a("bumpFilter", "bf", T::Float, 1)
        .a("bumpFilterOffset", "bfo", T::Float).a("bumpInterp", "bi", T::Enum).xyz("outNormal", "o", T::Float3, 0, 0, 0, U::None);
}

// Deformers evaluated by core/scene/deformer_eval.cpp and their handles. A nonLinear node carries
// its handle type's parameters as addAttr'd attributes, so only the shared ones are listed here;
// the handle shapes declare them with Maya's defaults (angles in radians).
void addDeformerTypes(Table& t) {
    t.type("geometryFilter", "node");
    t.a("envelope", "en", T::Float, 1).a("input", "ip", T::Compound, 0, U::None, true)
        .a("inputGeometry", "ig", T::Generic, 0, U::None, false, "input")
        .a("groupId", "gi", T::Int, 0, U::None, false, "input")
        .a("outputGeometry", "og", T::Generic, 0, U::None, true)
        .a("originalGeometry", "orggeom", T::Generic, 0, U::None, true);
    t.type("weightGeometryFilter", "geometryFilter");
    t.a("weightList", "wl", T::Compound, 0, U::None, true)
        .a("weights", "w", T::Double, 1, U::None, true, "weightList");
    t.type("tweak", "geometryFilter");
    t.a("relativeTweak", "rtw", T::Bool, 1).a("plist", "pl", T::Compound, 0, U::None, true)
        .c("controlPoints", "cp", T::Double3, {0, 0, 0, 0}, U::Distance,
           {{"xValue", "xv"}, {"yValue", "yv"}, {"zValue", "zv"}}, true, "plist")
        .a("vlist", "vl", T::Compound, 0, U::None, true)
        .c("vertex", "vt", T::Float3, {0, 0, 0, 0}, U::Distance,
           {{"xVertex", "vx"}, {"yVertex", "vy"}, {"zVertex", "vz"}}, true, "vlist");
    t.type("cluster", "weightGeometryFilter");
    t.a("matrix", "ma", T::Matrix).a("bindPreMatrix", "pm", T::Matrix)
        .a("clusterXforms", "x", T::Compound)
        .a("preMatrix", "pre", T::Matrix, 0, U::None, false, "clusterXforms")
        .a("weightedMatrix", "wt", T::Matrix, 0, U::None, false, "clusterXforms")
        .a("postMatrix", "post", T::Matrix, 0, U::None, false, "clusterXforms")
        .a("relative", "rel", T::Bool, 0).a("angleInterpolation", "ai", T::Enum, 0)
        .a("geomMatrix", "gm", T::Matrix, 0, U::None, true)
        .a("percentResolution", "ptr", T::Float, 5).a("usePartialResolution", "upr", T::Enum, 0);
    t.type("nonLinear", "weightGeometryFilter");
    t.a("deformerData", "dd", T::Generic).a("matrix", "ma", T::Matrix);
    t.type("skinCluster", "geometryFilter");
    t.a("weightList", "wl", T::Compound, 0, U::None, true)
        .a("weights", "w", T::Double, 0, U::None, true, "weightList")
        .a("matrix", "ma", T::Matrix, 0, U::None, true).a("bindPreMatrix", "pm", T::Matrix, 0, U::None, true)
        .a("geomMatrix", "gm", T::Matrix).a("normalizeWeights", "nw", T::Enum, 1)
        .a("skinningMethod", "skm", T::Enum, 0).a("blendWeights", "bw", T::Double, 0, U::None, true)
        .a("dropoff", "dpf", T::Double, 4, U::None, true).a("lockWeights", "lw", T::Bool, 0, U::None, true)
        .a("maintainMaxInfluences", "mmi", T::Bool, 0).a("maxInfluences", "mi", T::Int, 2)
        .a("bindMethod", "bm", T::Enum, 0).a("useComponents", "uc", T::Bool, 0)
        .a("useComponentsMatrix", "ucm", T::Bool, 0).a("bindPose", "bp", T::Message)
        .color("influenceColor", "ifcl", 0, 0, 0, "ifcl", true)
        .a("weightDistribution", "wd", T::Enum, 0);

    t.type("deformFunc", "shape");
    t.a("deformerData", "dd", T::Generic).a("handleWidth", "hw", T::Double, 1);
    t.type("deformBend", "deformFunc");
    t.a("curvature", "cur", T::Double, 0, U::Angle).a("lowBound", "lb", T::Double, -1).a("highBound", "hb", T::Double, 1);
    t.type("deformFlare", "deformFunc");
    t.a("lowBound", "lb", T::Double, -1).a("highBound", "hb", T::Double, 1)
        .a("startFlareX", "sfx", T::Double, 1).a("startFlareZ", "sfz", T::Double, 1)
        .a("endFlareX", "efx", T::Double, 1).a("endFlareZ", "efz", T::Double, 1).a("curve", "crv", T::Double, 0);
    t.type("deformSine", "deformFunc");
    t.a("amplitude", "amp", T::Double, 0).a("wavelength", "wav", T::Double, 2).a("offset", "off", T::Double, 0)
        .a("dropoff", "dr", T::Double, 0).a("lowBound", "lb", T::Double, -1).a("highBound", "hb", T::Double, 1);
    t.type("deformSquash", "deformFunc");
    t.a("factor", "fac", T::Double, 0).a("expand", "exp", T::Double, 1).a("maxExpandPos", "mp", T::Double, 0.5)
        .a("startSmoothness", "ss", T::Double, 0).a("endSmoothness", "es", T::Double, 0)
        .a("lowBound", "lb", T::Double, -1).a("highBound", "hb", T::Double, 1);
    t.type("deformTwist", "deformFunc");
    t.a("startAngle", "sa", T::Double, 0, U::Angle).a("endAngle", "ea", T::Double, 0, U::Angle)
        .a("lowBound", "lb", T::Double, -1).a("highBound", "hb", T::Double, 1);
    t.type("deformWave", "deformFunc");
    t.a("amplitude", "amp", T::Double, 0).a("wavelength", "wav", T::Double, 1).a("offset", "off", T::Double, 0)
        .a("dropoff", "dr", T::Double, 0).a("dropoffPosition", "dp", T::Double, 0)
        .a("minRadius", "mnr", T::Double, 0).a("maxRadius", "mxr", T::Double, 1);
    t.type("clusterHandle", "shape");
    t.xyz("origin", "or", T::Double3, 0, 0, 0, U::Distance)
        .a("clusterTransforms", "x", T::Compound, 0, U::None, true)
        .a("preWeightedMatrixTransform", "pre", T::Matrix, 0, U::None, false, "clusterTransforms")
        .a("weightedMatrixTransform", "wt", T::Matrix, 0, U::None, false, "clusterTransforms")
        .a("postWeightedMatrixTransform", "post", T::Matrix, 0, U::None, false, "clusterTransforms")
        .a("weightedNode", "wn", T::Message);
}

const Table& table() {
    static const Table instance = [] {
        Table t;
        addDagTypes(t);
        addLightTypes(t);
        addShadingTypes(t);
        addRenderSettingTypes(t);
        addAnimationTypes(t);
        addHistoryTypes(t);
        addMiscTypes(t);
        addDeformerTypes(t);
        for (auto& [name, schema] : t.m_types) {
            schema->finalize();
            t.m_byType.emplace(name, schema.get());
        }
        return t;
    }();
    return instance;
}

}  // namespace

const NodeSchema* findSchema(std::string_view type) {
    // Files create nodes of one type in runs (a million transforms, mesh after mesh): the last
    // schema found is tried first, by its own name, before the table is hashed.
    thread_local const NodeSchema* last = nullptr;
    if (last && last->type() == type) return last;
    const auto& types = table().m_byType;
    auto it = types.find(type);
    if (it == types.end()) return nullptr;
    last = it->second;
    return last;
}

std::vector<std::string> schemaTypes() {
    std::vector<std::string> out;
    for (auto& [name, s] : table().m_types) out.push_back(name);
    return out;
}

}  // namespace pushpin::scene
