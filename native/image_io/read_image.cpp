// The OpenImageIO reader module (read_image.h).  Byte images stay bytes (decoded per lookup when sRGB, as Cycles
// keeps them); every other pixel format is read as float.
#include "read_image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
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

extern "C" int sphrect_read_image(const char* path, SphrectImagePixels* out, char* error, size_t error_size) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return Fail("cannot be read (" + OIIO::geterror() + ")", error, error_size);
    const OIIO::ImageSpec& spec = in->spec();
    const int w = spec.width, h = spec.height, c = std::min(spec.nchannels, 4);
    if (w <= 0 || h <= 0 || c <= 0 || int64_t(w) * h > (int64_t(1) << 30))
        return Fail("has no usable size", error, error_size);
    const bool bytes = spec.format == OIIO::TypeDesc::UINT8;
    const size_t elem = bytes ? 1 : sizeof(float), row = size_t(w) * size_t(c) * elem;
    void* pixels = std::malloc(row * size_t(h));
    if (!pixels) return Fail("does not fit in memory", error, error_size);
    // OpenImageIO's rows run top to bottom, Blender's (and ours) bottom to top: read with a negative y stride
    // from the last row.
    char* last_row = static_cast<char*>(pixels) + row * size_t(h - 1);
    if (!in->read_image(0, 0, 0, c, bytes ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT, last_row, OIIO::AutoStride,
                        -OIIO::stride_t(row), OIIO::AutoStride)) {
        std::free(pixels);
        return Fail("could not be decoded (" + in->geterror() + ")", error, error_size);
    }
    *out = {w, h, c, bytes ? 1 : 0, pixels};
    return 1;
}

extern "C" void sphrect_free_image_pixels(void* pixels) { std::free(pixels); }
