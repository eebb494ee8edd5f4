// tests/support/ma_preamble.h: pieces of Maya ASCII text that the generated test scenes start
// from: the file header with a renderable perspective camera, and one grey shading group that
// shapes join.
#pragma once

#include <sstream>
#include <string>

namespace pushpin::test {

// The header lines of a Maya 2018 scene in centimetres and degrees, then the transform "persp" at
// (0, 0, cameraZ) with the renderable camera "perspShape" under it, looking down -Z.
inline std::string maPreamble(double cameraZ) {
    std::ostringstream z;
    z << cameraZ;  // shortest form: 7 -> "7", as a hand-written scene would have it
    return R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "persp";
	setAttr ".t" -type "double3" 0 0 )" +
           z.str() + R"(;
createNode camera -n "perspShape" -p "persp";
	setAttr ".rnd" yes;
)";
}

// A lambert "grey" and its shading group "greySG" in the render partition. A shape joins it with
// connectAttr "<shape>.iog" "greySG.dsm" -na.
inline std::string greyShadingGroup() {
    return R"(createNode lambert -n "grey";
createNode shadingEngine -n "greySG";
connectAttr "greySG.pa" ":renderPartition.st" -na;
connectAttr "grey.oc" "greySG.ss";
)";
}

}  // namespace pushpin::test
