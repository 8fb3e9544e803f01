// The OpenImageIO reader module (read_image.h).  Byte images stay bytes (decoded per lookup when sRGB, as Cycles
// keeps them); every other pixel format is read as float.
#include "read_image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

namespace {

int Fail(const std::string& why, char* error, size_t error_size) {
    if (error_size > 0) {
        std::strncpy(error, why.c_str(), error_size - 1);
        error[error_size - 1] = 0;
    }
    return 0;
}

}  // namespace

extern "C" int sphrect_read_image(const char* path, SphrectImageAllocateFn allocate, void* context,
                                  SphrectImagePixels* out, char* error, size_t error_size) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return Fail("cannot be read (" + OIIO::geterror() + ")", error, error_size);
    const OIIO::ImageSpec& spec = in->spec();
    const int w = spec.width, h = spec.height, c = std::min(spec.nchannels, 4);
    if (w <= 0 || h <= 0 || c <= 0 || int64_t(w) * h > (int64_t(1) << 30))
        return Fail("has no usable size", error, error_size);
    const bool bytes = spec.format == OIIO::TypeDesc::UINT8;
    const size_t elem = bytes ? 1 : sizeof(float), row = size_t(w) * size_t(c) * elem;
    void* pixels = allocate(context, w, h, c, bytes ? 1 : 0, error, error_size);
    if (!pixels) return 0;
    // OpenImageIO's rows run top to bottom, Blender's (and ours) bottom to top: each file row goes to its place a
    // band at a time, so that nothing the size of the image is allocated beside `pixels` (read_image with a
    // negative stride decoded into a whole buffer of its own first).
    const OIIO::TypeDesc type = bytes ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    char* rows = static_cast<char*>(pixels);
    if (spec.tile_width > 0) {  // tiled files: read whole, then flipped in place
        if (!in->read_image(0, 0, 0, c, type, pixels))
            return Fail("could not be decoded (" + in->geterror() + ")", error, error_size);
        for (size_t top = 0, bottom = size_t(h) - 1; top < bottom; ++top, --bottom)
            std::swap_ranges(rows + top * row, rows + (top + 1) * row, rows + bottom * row);
    } else {
        for (int y = 0; y < h; ++y)
            if (!in->read_scanlines(0, 0, spec.y + y, spec.y + y + 1, spec.z, 0, c, type,
                                    rows + row * size_t(h - 1 - y)))
                return Fail("could not be decoded (" + in->geterror() + ")", error, error_size);
    }
    *out = {w, h, c, bytes ? 1 : 0, pixels};
    return 1;
}
