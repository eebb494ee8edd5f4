// tools/makebot/oiio_loader.cpp: loads makebot-oiio.so on first use (tools/makebot/oiio_module.h).
#include <dlfcn.h>

#include <mutex>
#include <string>
#include <system_error>

#include "cache/error.h"
#include "tools/makebot/oiio_module.h"

namespace pushpin::makebot {
namespace {

struct Module {
    MakebotOiioOpenFn* open = nullptr;
    MakebotOiioReadFn* read = nullptr;
    MakebotOiioCloseFn* close = nullptr;
    std::string error;  // why it could not be loaded
};

// Loaded once and kept for the life of the process (the readers' info strings point into it).
const Module& module() {
    static const Module loaded = [] {
        Module m;
        std::error_code ec;
        const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
        const std::filesystem::path file = (ec ? std::filesystem::path(".") : self.parent_path()) / kOiioModuleName;
        void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = ::dlerror();
            m.error = "cannot load the OpenImageIO reader " + file.string() + (why ? std::string(": ") + why : "");
            return m;
        }
        auto version = reinterpret_cast<MakebotOiioVersionFn*>(::dlsym(handle, "pushpin_makebot_oiio_version"));
        m.open = reinterpret_cast<MakebotOiioOpenFn*>(::dlsym(handle, "pushpin_makebot_oiio_open"));
        m.read = reinterpret_cast<MakebotOiioReadFn*>(::dlsym(handle, "pushpin_makebot_oiio_read"));
        m.close = reinterpret_cast<MakebotOiioCloseFn*>(::dlsym(handle, "pushpin_makebot_oiio_close"));
        if (!version || !m.open || !m.read || !m.close || version() != kMakebotOiioModuleVersion) {
            m.open = nullptr;
            m.error = "the OpenImageIO reader " + file.string() + " is not the one this makebot was built with";
        }
        return m;
    }();
    return loaded;
}

class ModuleRowSource final : public texture::RowSource {
public:
    ModuleRowSource(const Module& m, void* reader, const texture::RowSourceInfo& info) : m_module(m), m_reader(reader) {
        m_info = info;
    }
    ~ModuleRowSource() override { m_module.close(m_reader); }
    ModuleRowSource(const ModuleRowSource&) = delete;
    ModuleRowSource& operator=(const ModuleRowSource&) = delete;

    void read(uint32_t y0, uint32_t rows, float* out) override {
        char message[2048] = {};
        if (m_module.read(m_reader, y0, rows, out, message, sizeof message) != 0) throw Error(message);
    }

private:
    const Module& m_module;
    void* m_reader;
};

}  // namespace

std::unique_ptr<texture::RowSource> openOiioRowSourceFromModule(const std::filesystem::path& path) {
    const Module& m = module();
    if (!m.open) throw Error(m.error);
    texture::RowSourceInfo info;
    char message[2048] = {};
    void* reader = m.open(path.c_str(), &info, message, sizeof message);
    if (!reader) throw Error(message);
    return std::make_unique<ModuleRowSource>(m, reader, info);
}

}  // namespace pushpin::makebot
