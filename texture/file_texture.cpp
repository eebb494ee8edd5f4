// texture/file_texture.cpp: resolving a file node's image and evaluating it over a batch.
#include "texture/file_texture.h"

#include <algorithm>
#include <cmath>

#include "texture/detail/page_source.h"

namespace pushpin::texture {

LookupOptions fileLookupOptions(const FileTextureParams& p) {
    LookupOptions o;
    o.widthScale = p.filter;
    o.widthOffset = p.filterOffset;
    switch (p.filterType) {
    case 0: o.filter = FilterMode::Point; break;
    case 2: o.filter = FilterMode::Kernel; o.kernel = KernelShape::Box; break;
    case 3: o.filter = FilterMode::Kernel; o.kernel = KernelShape::Quadratic; break;
    case 4: o.filter = FilterMode::Kernel; o.kernel = KernelShape::Quartic; break;
    case 5: o.filter = FilterMode::Kernel; o.kernel = KernelShape::Gaussian; break;
    case 1:
    default:
        o.filter = FilterMode::Trilinear;
        o.maxAnisotropy = std::max(1u, p.maxAnisotropy);
        break;
    }
    return o;
}

FileTexture::FileTexture(TextureCache& cache, const std::filesystem::path& path,
                         const FileTextureOptions& options)
    : m_cache(&cache), m_path(path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        cache.warn("file texture '" + path.string() + "' not found; using the default colour");
        return;
    }
    if (isBotFile(path)) {
        m_handle = cache.registerFile(path);
        m_botPath = path;
        return;
    }
    std::string why;
    if (options.useTextureCache) {
        const AutoConvertResult r = convertToBot(path, options.convert);
        if (r.ok()) {
            m_handle = cache.registerFile(r.botPath);
            m_botPath = r.botPath;
            return;
        }
        why = r.error;
    }
    try {
        const LoadedImage img = loadImage(path, options.convert.maxChannels);
        m_handle = cache.registerSource(detail::makeMemoryPageSource(
            path, img.pixels.data(), img.width, img.height, img.channels, WrapMode::Periodic,
            WrapMode::Periodic));
        if (!why.empty())
            cache.warn("cannot convert texture '" + path.string() + "' into " +
                       conversionDir(options.convert).string() + " (" + why +
                       "); reading it into memory instead");
    } catch (const std::exception& ex) {
        cache.warn("cannot read file texture '" + path.string() + "': " + ex.what() +
                   "; using the default colour");
        m_handle = TextureHandle{};
    }
}

bool FileTexture::usable() const { return m_handle.valid() && !m_cache->broken(m_handle); }

void FileTexture::evaluate(TextureCache::PerThread& thread, const FileTextureParams& params,
                           const FileTextureBatch& batch) const {
    const TextureInfo* info = m_handle.valid() ? m_cache->info(m_handle) : nullptr;
    if (!info) {
        std::fill(batch.r, batch.r + batch.count, params.defaultColor[0]);
        std::fill(batch.g, batch.g + batch.count, params.defaultColor[1]);
        std::fill(batch.b, batch.b + batch.count, params.defaultColor[2]);
        std::fill(batch.a, batch.a + batch.count, params.defaultAlpha);
        return;
    }
    const LookupOptions options = fileLookupOptions(params);
    const uint32_t channels = info->channels;
    // Where each texture channel goes, and what a missing one holds.
    float* outs[4];
    float fill[4];
    constexpr size_t kChunk = 64;
    switch (channels) {
    case 1:
        outs[0] = batch.r; fill[0] = params.defaultColor[0];
        break;
    case 2:
        outs[0] = batch.r; fill[0] = params.defaultColor[0];
        outs[1] = batch.a; fill[1] = params.defaultAlpha;
        break;
    default:
        outs[0] = batch.r; fill[0] = params.defaultColor[0];
        outs[1] = batch.g; fill[1] = params.defaultColor[1];
        outs[2] = batch.b; fill[2] = params.defaultColor[2];
        outs[3] = batch.a; fill[3] = params.defaultAlpha;  // used only with 4 channels
        break;
    }
    const uint32_t used = std::min(channels, 4u);
    // Maya's v runs up from the bottom row; texture t runs down from the top row.
    float t[kChunk], dtdx[kChunk], dtdy[kChunk];
    for (size_t first = 0; first < batch.count; first += kChunk) {
        const size_t n = std::min(kChunk, batch.count - first);
        for (size_t i = 0; i < n; ++i) {
            t[i] = 1.0f - batch.v[first + i];
            dtdx[i] = batch.dvdx ? -batch.dvdx[first + i] : 0.0f;
            dtdy[i] = batch.dvdy ? -batch.dvdy[first + i] : 0.0f;
        }
        LookupBatch lb;
        lb.count = n;
        lb.s = batch.u + first;
        lb.t = t;
        lb.dsdx = batch.dudx ? batch.dudx + first : nullptr;
        lb.dsdy = batch.dudy ? batch.dudy + first : nullptr;
        lb.dtdx = dtdx;
        lb.dtdy = dtdy;
        float* chunkOut[4];
        for (uint32_t c = 0; c < used; ++c) chunkOut[c] = outs[c] + first;
        const bool ok = sampleTexture(thread, m_handle, options, lb, fill, used, chunkOut);
        if (!ok) {
            // Broken (now or earlier): the whole result is the default colour, as documented.
            for (size_t i = first; i < first + n; ++i) {
                batch.r[i] = params.defaultColor[0];
                batch.g[i] = params.defaultColor[1];
                batch.b[i] = params.defaultColor[2];
                batch.a[i] = params.defaultAlpha;
            }
            continue;
        }
        if (channels <= 2) {
            std::copy(batch.r + first, batch.r + first + n, batch.g + first);
            std::copy(batch.r + first, batch.r + first + n, batch.b + first);
        }
        if (channels == 1 || channels == 3)
            std::fill(batch.a + first, batch.a + first + n, 1.0f);
        // Samples with non-finite uv get the whole default colour, not a grey copy of it.
        for (size_t i = first; i < first + n; ++i)
            if (!std::isfinite(batch.u[i]) || !std::isfinite(batch.v[i])) {
                batch.r[i] = params.defaultColor[0];
                batch.g[i] = params.defaultColor[1];
                batch.b[i] = params.defaultColor[2];
                batch.a[i] = params.defaultAlpha;
            }
    }
}

}  // namespace pushpin::texture
