// RenderScene::LoadImage: an image file named by a scene (outside Blender), read by the OpenImageIO reader
// module (image_io/read_image.h), loaded on first use.  A file that cannot be read -- or no reader -- becomes
// Cycles' missing image, magenta, with a warning: the render goes on and shows where the image was, as Cycles
// does.
#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "image_io/read_image.h"
#include "scene.h"

namespace sphrect::render {

namespace {

struct ImageReader {
    SphrectReadImageFn read = nullptr;
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
            if (reader.read) return;
            reader.error = path + " has no sphrect_read_image";
        }
        reader.read = nullptr;
    });
    return reader;
}

// A file's pixels that some scene still holds, so that another scene reading the same unchanged file (the add-on's
// compare builds up to 20 renderers of one scene) shares them instead of decoding its own copy.
struct HeldFile {
    std::weak_ptr<const void> storage;
    int width = 0, height = 0, channels = 0;
    const uint8_t* bytes = nullptr;
    const float* floats = nullptr;
};

std::mutex held_files_mutex;
std::map<std::string, HeldFile> held_files;  // by FileIdentity

// The file's canonical path, size and modification time: a file changed since it was read is read again.
std::string FileIdentity(const std::string& path, std::error_code& error_code) {
    namespace fs = std::filesystem;
    const fs::path canonical = fs::canonical(path, error_code);
    if (error_code) return {};
    const auto size = fs::file_size(canonical, error_code);
    if (error_code) return {};
    const auto time = fs::last_write_time(canonical, error_code);
    if (error_code) return {};
    return canonical.string() + '\n' + std::to_string(size) + '\n' + std::to_string(time.time_since_epoch().count());
}

// What sphrect_read_image decodes into: room the scene's memory limit allows, owned here.
struct DecodeRoom {
    const RenderScene* scene;
    std::string who;
    std::shared_ptr<void> storage;
    std::string refused;  // the memory check's message, when it refused the image

    static void* Allocate(void* context, int width, int height, int channels, int bytes, char* error,
                          size_t error_size) {
        DecodeRoom& room = *static_cast<DecodeRoom*>(context);
        const uint64_t size = ImageStorageBytes(width, height, channels, bytes != 0);
        try {
            room.scene->CheckImageMemory(room.who, size);
        } catch (const std::invalid_argument& e) {
            room.refused = e.what();
            std::snprintf(error, error_size, "refused by the memory limit");
            return nullptr;
        }
        room.storage.reset(std::malloc(size_t(size)), std::free);
        if (!room.storage) std::snprintf(error, error_size, "does not fit in memory");
        return room.storage.get();
    }
};

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
    const std::string who = "image '" + name + "' (" + path + ")";
    const std::string identity = FileIdentity(path, error_code);
    if (!identity.empty()) {
        std::lock_guard<std::mutex> lock(held_files_mutex);
        const auto it = held_files.find(identity);
        if (it != held_files.end()) {
            const HeldFile& held = it->second;
            if (auto storage = held.storage.lock()) {
                CheckImageMemory(who, ImageStorageBytes(held.width, held.height, held.channels, held.bytes != nullptr));
                return AddImage(ShareImage(name, held.width, held.height, held.channels, held.bytes, held.floats,
                                           std::move(storage), srgb));
            }
        }
    }
    const ImageReader& reader = Reader();
    if (!reader.read) return missing("no OpenImageIO reader module (" + reader.error + ")");
    SphrectImagePixels im{};
    char error[512] = {0};
    DecodeRoom room{this, who, nullptr, ""};
    if (!reader.read(path.c_str(), &DecodeRoom::Allocate, &room, &im, error, sizeof error)) {
        if (!room.refused.empty()) throw std::invalid_argument(room.refused);
        return missing(error);
    }
    const size_t values = size_t(im.width) * size_t(im.height) * size_t(im.channels);
    const uint8_t* bytes = im.bytes ? static_cast<const uint8_t*>(im.pixels) : nullptr;
    const float* floats = nullptr;
    if (!im.bytes) {
        ZeroNonFinite(static_cast<float*>(im.pixels), values);
        floats = static_cast<const float*>(im.pixels);
    }
    if (!identity.empty()) {
        std::lock_guard<std::mutex> lock(held_files_mutex);
        for (auto it = held_files.begin(); it != held_files.end();)  // forget the files no scene holds any more
            it = it->second.storage.expired() ? held_files.erase(it) : std::next(it);
        held_files[identity] = {room.storage, im.width, im.height, im.channels, bytes, floats};
    }
    return AddImage(ShareImage(name, im.width, im.height, im.channels, bytes, floats, std::move(room.storage), srgb));
}

}  // namespace sphrect::render
