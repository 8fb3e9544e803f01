// RenderScene::LoadImage: an image file named by a scene (outside Blender), read by the OpenImageIO reader
// module (image_io/read_image.h), loaded on first use.  A file that cannot be read -- or no reader -- becomes
// Cycles' missing image, magenta, with a warning: the render goes on and shows where the image was, as Cycles
// does.
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>

#include "image_io/read_image.h"
#include "scene.h"

namespace sphrect::render {

namespace {

struct ImageReader {
    SphrectReadImageFn read = nullptr;
    SphrectFreeImagePixelsFn free = nullptr;
    std::string error;
};

// The module: SPHRECT_IMAGE_IO if set, else next to the shared object holding this code (the Python package's
// _native), else where the build put it.
const ImageReader& Reader() {
    static ImageReader reader;
    static std::once_flag once;
    std::call_once(once, [] {
        std::string candidates[3];
        if (const char* env = std::getenv("SPHRECT_IMAGE_IO")) candidates[0] = env;
        Dl_info info;
        if (dladdr(reinterpret_cast<void*>(&Reader), &info) && info.dli_fname) {
            const std::string self = info.dli_fname;
            candidates[1] = self.substr(0, self.find_last_of('/') + 1) + "libsphrect_image_io.so";
        }
        candidates[2] = SPHRECT_IMAGE_IO_BUILD_PATH;
        for (const std::string& path : candidates) {
            if (path.empty()) continue;
            void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
            if (!lib) {
                reader.error = dlerror();
                continue;
            }
            reader.read = reinterpret_cast<SphrectReadImageFn>(dlsym(lib, "sphrect_read_image"));
            reader.free = reinterpret_cast<SphrectFreeImagePixelsFn>(dlsym(lib, "sphrect_free_image_pixels"));
            if (reader.read && reader.free) return;
            reader.error = path + " has no sphrect_read_image";
        }
        reader.read = nullptr;
    });
    return reader;
}

}  // namespace

int RenderScene::LoadImage(const std::string& name, const std::string& path, bool srgb) {
    RequireNotCommitted();
    auto missing = [&](const std::string& why) {
        warnings.push_back("image '" + name + "' (" + path + "): " + why + "; shown magenta, as Cycles does");
        const float magenta[4] = {kMissingImageColor.r, kMissingImageColor.g, kMissingImageColor.b,
                                  kMissingImageColor.a};
        return AddImage(name, 1, 1, 4, nullptr, magenta, false);
    };
    // Only a regular file is an image: a device (/dev/zero), a FIFO or a folder would make the reader spin or block
    // forever.  A path with a NUL byte names another file than the one asked for.
    if (path.find('\0') != std::string::npos) return missing("the path holds a NUL byte");
    std::error_code error_code;
    if (!std::filesystem::is_regular_file(path, error_code))
        return missing(std::filesystem::exists(path, error_code) ? "not a regular file" : "no such file");
    const ImageReader& reader = Reader();
    if (!reader.read) return missing("no OpenImageIO reader module (" + reader.error + ")");
    SphrectImagePixels im{};
    char error[512] = {0};
    if (!reader.read(path.c_str(), &im, error, sizeof error)) return missing(error);
    int id;
    try {
        id = AddImage(name, im.width, im.height, im.channels,
                      im.bytes ? static_cast<const uint8_t*>(im.pixels) : nullptr,
                      im.bytes ? nullptr : static_cast<const float*>(im.pixels), srgb);
    } catch (...) {
        reader.free(im.pixels);
        throw;
    }
    reader.free(im.pixels);
    return id;
}

}  // namespace sphrect::render
