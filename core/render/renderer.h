// core/render/renderer.h: renders one camera's view of a FrameScene (DESIGN.md steps 4, 6b–e, 7):
// visible set (far-plane culling per object, frustum culling by screen-space bounds, near-plane
// clipping of triangles, back faces of single-sided objects dropped), tiles rendered in parallel
// with oneTBB, Exact Area Sampling visibility, shading of merged fragments in vectors of samples,
// adaptive shading by contrast at the Highest level, box or multi-pixel filtering of fragments,
// and the background.
// Per tile, objects are taken front to back; one that nearer opaque geometry already rasterized in
// the tile hides in every pixel it reaches is neither tessellated nor rasterized there
// (PixelResolver::occludingDepth), which changes no bit of the image.
// Thread safety: renderFrame() runs its own parallel loop; the FrameScene and camera are read-only.
// Determinism: the image depends only on the scene, camera and settings — not on the thread
// count, the tile size or the tile order. At the Highest level the contrast test reads base
// colours around each pixel (two columns left, one right, one row above): a tile reads those of
// tiles already done from what they kept (contrast_borders.h) and renders only the part of that
// margin lying in tiles not done yet. A multi-pixel filter renders no margin: a pixel whose window
// reaches past its tile is filtered once the tiles around it are done, from the surfaces they kept
// near their edges (filter_borders.h), summed in the same order as inside a tile.
// Files: the frame's layout and up-front memory (frame_memory.h), the visible set
// (visible_set.h), the tile plan (tile_plan.h), each tile's objects (tile_objects.h), lazy
// tessellation (lazy_tessellation.h), camera space and the near clip (camera_space.h), Exact Area
// Sampling (visibility.h), shading points (shading_points.h), adaptive shading
// (adaptive_shading.h), the pixel filter (pixel_filter.h) and the stats (render_stats.h);
// renderer.cpp runs the tiles through them.
// Memory: before it allocates, renderFrame charges one MemoryBudget (RenderOptions::memoryBudget,
// else its own with the cap of memoryCap(settings)) with every buffer whose size it knows
// (frameMemory()): "framebuffer" for the frame, the image writer's copy and the adaptive mask,
// "fragments" for the tile list and each thread's share of the tile buffers, "tessellation" for
// each object's view, "geometry" for the sources that stay resident. A frame the cap cannot hold
// fails with pushpin::MemoryCapError before any of them is allocated. Tessellations are made when a
// tile first needs them and kept in an LRU charged as "tessellation" (lazy_tessellation.h), and a
// tile's buffers beyond its thread's share are charged as "fragments" as they grow; a tile that
// cannot fit stops the render with MemoryCapError too. Every charge is released when renderFrame
// returns or throws.
#pragma once

#include "core/render/camera.h"
#include "core/render/frame_memory.h"
#include "core/render/frame_scene.h"
#include "core/render/framebuffer.h"
#include "core/render/render_options.h"
#include "core/render/render_settings.h"
#include "core/render/render_stats.h"

namespace pushpin::render {

// Renders `camera`'s view. The framebuffer has the camera's size; pixels outside the render
// region (settings.useRenderRegion) stay 0. Depth is kept when settings.depth is set.
// Uses settings.numCpusToUse threads (0: all). Inputs come checked from buildFrameScene and
// makeRenderCamera (numbers at the door); every pixel written is then finite for finite shading.
// Memory: charges frameMemory() to the budget (see the top of this file) before allocating and
// releases it before returning. Throws pushpin::MemoryCapError, with nothing large allocated,
// when the budget cannot take it, e.g. "the 32768x32768 frame needs 36.0 GB of buffers, over the
// memory cap of 2048 MB (-mm)". std::bad_alloc passes through.
Framebuffer renderFrame(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings,
                        RenderStats& stats, const RenderOptions& options = {});

}  // namespace pushpin::render
