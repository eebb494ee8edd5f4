// texture/file_texture.h: what Maya's `file` texture node calls: colour and alpha for a batch of
// uv coordinates with screen-space derivatives, filtered the way the node's filterType, filter
// and filterOffset ask, through the shared TextureCache.
// Resolution happens once, when the scene loads: a BOT file is registered as is; any other image
// is converted once into TMPDIR when useTextureCache is on (texture/auto_convert.h), and read
// into memory with OpenImageIO otherwise or when conversion fails (with one warning).
// Thread safety: evaluate() may run in many threads at once, each with its own PerThread.
// Memory: a BOT texture costs its page table; an image read into memory costs its float pyramid
// (about 4/3 × width × height × channels × 4 bytes), which the caller should charge to the budget.
#pragma once

#include <cstddef>
#include <filesystem>

#include "texture/auto_convert.h"
#include "texture/texture_cache.h"
#include "texture/texture_sampler.h"

namespace pushpin::texture {

// The file node's attributes that shape a lookup (Maya names and defaults).
struct FileTextureParams {
    // 0 Off, 1 Mipmap, 2 Box, 3 Quadratic, 4 Quartic, 5 Gaussian (see fileLookupOptions()).
    int filterType = 3;
    float filter = 1.0f;        // multiplies the footprint width
    float filterOffset = 0.0f;  // added to the footprint width, in uv units
    float defaultColor[3] = {0.5f, 0.5f, 0.5f};
    float defaultAlpha = 1.0f;
    uint32_t maxAnisotropy = 1;  // Mipmap only: probes along the footprint's major axis
};

// Maps the file node's filter attributes onto a lookup:
//   0 Off        FilterMode::Point at level 0 (no filtering; filter and filterOffset unused)
//   1 Mipmap     FilterMode::Trilinear, anisotropic when maxAnisotropy > 1
//   2 Box        FilterMode::Kernel, KernelShape::Box        (see texture_sampler.h for shapes)
//   3 Quadratic  FilterMode::Kernel, KernelShape::Quadratic
//   4 Quartic    FilterMode::Kernel, KernelShape::Quartic
//   5 Gaussian   FilterMode::Kernel, KernelShape::Gaussian
// with widthScale = filter and widthOffset = filterOffset. Other values fall back to Mipmap.
LookupOptions fileLookupOptions(const FileTextureParams& params);

// Struct-of-arrays batch. Inputs are Maya uv (v = 0 at the bottom of the image) and their
// derivatives with respect to screen x and y; derivative arrays may be null (treated as zero).
struct FileTextureBatch {
    size_t count = 0;
    const float* u = nullptr;
    const float* v = nullptr;
    const float* dudx = nullptr;
    const float* dudy = nullptr;
    const float* dvdx = nullptr;
    const float* dvdy = nullptr;
    float* r = nullptr;
    float* g = nullptr;
    float* b = nullptr;
    float* a = nullptr;
};

struct FileTextureOptions {
    bool useTextureCache = true;  // convert non-BOT images into TMPDIR (render globals' setting)
    AutoConvertOptions convert;
};

class FileTexture {
public:
    // Resolves `path` and registers it with `cache`. Never throws: a missing or unreadable file
    // gives one warning naming the path (through cache.warn()) and a texture that returns the
    // default colour.
    FileTexture(TextureCache& cache, const std::filesystem::path& path,
                const FileTextureOptions& options = {});

    const std::filesystem::path& path() const { return m_path; }
    // The BOT file actually read (the converted one for non-BOT images); empty when the image was
    // read into memory or could not be used.
    const std::filesystem::path& botPath() const { return m_botPath; }
    TextureHandle handle() const { return m_handle; }
    // False once the texture is missing, unreadable or broken.
    bool usable() const;

    // Colour and alpha of every sample. Channels: 1 grey (alpha 1), 2 grey + alpha, 3 RGB
    // (alpha 1), 4 RGBA. Broken or missing texture: default colour and alpha. Never throws.
    void evaluate(TextureCache::PerThread& thread, const FileTextureParams& params,
                  const FileTextureBatch& batch) const;

private:
    TextureCache* m_cache;
    std::filesystem::path m_path;
    std::filesystem::path m_botPath;
    TextureHandle m_handle;
};

}  // namespace pushpin::texture
