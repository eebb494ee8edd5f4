// texture/lookup_trace.cpp: the lookup trace writer and reader.
#include "texture/lookup_trace.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>

#include "cache/error.h"

namespace pushpin::texture {
namespace {

constexpr char kMagic[8] = {'P', 'P', 'T', 'R', 'A', 'C', 'E', '1'};
constexpr uint32_t kVersion = 1;
constexpr uint8_t kTextureChunk = 1;
constexpr uint8_t kBatchChunk = 2;
constexpr size_t kFlushBytes = size_t(1) << 20;

}  // namespace

LookupTraceWriter::LookupTraceWriter(const std::filesystem::path& path) : m_path(path) {
    m_file = std::fopen(path.c_str(), "wb");
    if (!m_file) throw IoError(path, "create lookup trace", errno);
    m_buffer.reserve(kFlushBytes + 4096);
    std::lock_guard lock(m_mutex);
    put(kMagic, sizeof kMagic);
    put(&kVersion, sizeof kVersion);
}

LookupTraceWriter::~LookupTraceWriter() {
    try {
        close();
    } catch (const std::exception& ex) {
        std::cerr << "pushpin: warning: " << ex.what() << "\n";
    }
}

void LookupTraceWriter::put(const void* bytes, size_t n) {
    const auto* b = static_cast<const uint8_t*>(bytes);
    m_buffer.insert(m_buffer.end(), b, b + n);
    if (m_buffer.size() >= kFlushBytes && m_file && !m_errno) {
        if (std::fwrite(m_buffer.data(), 1, m_buffer.size(), m_file) != m_buffer.size())
            m_errno = errno ? errno : EIO;
        m_buffer.clear();
    }
}

void LookupTraceWriter::record(uint32_t textureId, const std::filesystem::path& texturePath,
                               const LookupOptions& options, const LookupBatch& batch) {
    std::lock_guard lock(m_mutex);
    if (!m_file || m_errno || batch.count == 0) return;
    if (m_declared.insert(textureId).second) {
        const std::string p = texturePath.string();
        const uint32_t len = uint32_t(p.size());
        put(&kTextureChunk, 1);
        put(&textureId, 4);
        put(&len, 4);
        put(p.data(), len);
    }
    const uint8_t head[6] = {kBatchChunk,
                             uint8_t(options.filter),
                             uint8_t(options.kernel),
                             uint8_t(options.overrideWrap ? 1 : 0),
                             uint8_t(options.wrapS),
                             uint8_t(options.wrapT)};
    put(head, 1);
    put(&textureId, 4);
    put(head + 1, 5);
    put(&options.maxAnisotropy, 4);
    put(&options.widthScale, 4);
    put(&options.widthOffset, 4);
    const uint32_t count = uint32_t(batch.count);
    put(&count, 4);
    for (size_t i = 0; i < batch.count; ++i) {
        const float rec[6] = {batch.s[i],
                              batch.t[i],
                              batch.dsdx ? batch.dsdx[i] : 0.0f,
                              batch.dsdy ? batch.dsdy[i] : 0.0f,
                              batch.dtdx ? batch.dtdx[i] : 0.0f,
                              batch.dtdy ? batch.dtdy[i] : 0.0f};
        put(rec, sizeof rec);
    }
    m_lookups += batch.count;
}

void LookupTraceWriter::close() {
    std::lock_guard lock(m_mutex);
    if (!m_file) {
        if (m_errno) throw IoError(m_path, "write lookup trace", m_errno);
        return;
    }
    if (!m_errno && !m_buffer.empty() &&
        std::fwrite(m_buffer.data(), 1, m_buffer.size(), m_file) != m_buffer.size())
        m_errno = errno ? errno : EIO;
    m_buffer.clear();
    if (std::fclose(m_file) != 0 && !m_errno) m_errno = errno ? errno : EIO;
    m_file = nullptr;
    if (m_errno) throw IoError(m_path, "write lookup trace", m_errno);
}

uint64_t LookupTraceWriter::recordedLookups() const {
    std::lock_guard lock(m_mutex);
    return m_lookups;
}

LookupBatch TraceBatch::view() const {
    LookupBatch b;
    b.count = s.size();
    b.s = s.data();
    b.t = t.data();
    b.dsdx = dsdx.data();
    b.dsdy = dsdy.data();
    b.dtdx = dtdx.data();
    b.dtdy = dtdy.data();
    return b;
}

uint64_t LookupTrace::lookupCount() const {
    uint64_t n = 0;
    for (const TraceBatch& b : batches) n += b.s.size();
    return n;
}

LookupTrace readLookupTrace(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path, "open lookup trace", errno);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    if (in.bad()) throw IoError(path, "read lookup trace", errno);
    size_t pos = 0;
    auto fail = [&](const std::string& what) {
        throw FormatError(path, what + " at byte " + std::to_string(pos));
    };
    auto get = [&](void* dst, size_t n) {
        if (bytes.size() - pos < n) fail("truncated lookup trace");
        std::memcpy(dst, bytes.data() + pos, n);
        pos += n;
    };
    char magic[8];
    uint32_t version = 0;
    get(magic, 8);
    if (std::memcmp(magic, kMagic, 8) != 0) fail("not a pushpin lookup trace");
    get(&version, 4);
    if (version != kVersion) fail("unsupported lookup trace version " + std::to_string(version));
    LookupTrace trace;
    std::vector<bool> declared;
    while (pos < bytes.size()) {
        uint8_t kind = 0;
        get(&kind, 1);
        uint32_t id = 0;
        get(&id, 4);
        if (kind == kTextureChunk) {
            uint32_t len = 0;
            get(&len, 4);
            if (bytes.size() - pos < len) fail("truncated texture name");
            if (id >= (1u << 20)) fail("texture id out of range");
            if (trace.textures.size() <= id) {
                trace.textures.resize(id + 1);
                declared.resize(id + 1);
            }
            trace.textures[id] =
                std::string(reinterpret_cast<const char*>(bytes.data() + pos), len);
            declared[id] = true;
            pos += len;
        } else if (kind == kBatchChunk) {
            if (id >= declared.size() || !declared[id]) fail("batch names an undeclared texture");
            TraceBatch b;
            b.texture = id;
            uint8_t head[5];
            get(head, 5);
            if (head[0] > uint8_t(FilterMode::Kernel) || head[1] > uint8_t(KernelShape::Gaussian) ||
                head[2] > 1 || head[3] > uint8_t(WrapMode::Mirror) || head[4] > uint8_t(WrapMode::Mirror))
                fail("invalid lookup options");
            b.options.filter = FilterMode(head[0]);
            b.options.kernel = KernelShape(head[1]);
            b.options.overrideWrap = head[2] != 0;
            b.options.wrapS = WrapMode(head[3]);
            b.options.wrapT = WrapMode(head[4]);
            get(&b.options.maxAnisotropy, 4);
            get(&b.options.widthScale, 4);
            get(&b.options.widthOffset, 4);
            uint32_t count = 0;
            get(&count, 4);
            if ((bytes.size() - pos) / 24 < count) fail("truncated lookup batch");
            for (auto* v : {&b.s, &b.t, &b.dsdx, &b.dsdy, &b.dtdx, &b.dtdy}) v->resize(count);
            for (uint32_t i = 0; i < count; ++i) {
                float rec[6];
                get(rec, sizeof rec);
                b.s[i] = rec[0];
                b.t[i] = rec[1];
                b.dsdx[i] = rec[2];
                b.dsdy[i] = rec[3];
                b.dtdx[i] = rec[4];
                b.dtdy[i] = rec[5];
            }
            trace.batches.push_back(std::move(b));
        } else {
            pos -= 5;
            fail("unknown chunk kind " + std::to_string(kind));
        }
    }
    return trace;
}

}  // namespace pushpin::texture
