// RenderScene::LoadImage: an image file named by a scene (outside Blender), read with OpenImageIO.
// Byte images stay bytes (decoded per lookup when sRGB, as Cycles keeps them); every other pixel
// format is read as float.  A file that cannot be read becomes Cycles' missing image, magenta, with
// a warning: the render goes on and shows where the image was, as Cycles does.
#include <OpenImageIO/imageio.h>

#include <memory>
#include <vector>

#include "scene.h"

namespace sphrect::render {

int RenderScene::LoadImage(const std::string& name, const std::string& path, bool srgb) {
    RequireNotCommitted();
    auto missing = [&](const std::string& why) {
        warnings.push_back("image '" + name + "' (" + path + "): " + why + "; shown magenta, as Cycles does");
        const float magenta[4] = {kMissingImageColor.r, kMissingImageColor.g, kMissingImageColor.b,
                                  kMissingImageColor.a};
        return AddImage(name, 1, 1, 4, nullptr, magenta, false);
    };
    auto in = OIIO::ImageInput::open(path);
    if (!in) return missing("cannot be read (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec& spec = in->spec();
    const int w = spec.width, h = spec.height, c = std::min(spec.nchannels, 4);
    if (w <= 0 || h <= 0 || c <= 0 || int64_t(w) * h > (int64_t(1) << 30)) return missing("has no usable size");
    const bool bytes = spec.format == OIIO::TypeDesc::UINT8;
    const size_t row = size_t(w) * size_t(c);
    std::vector<uint8_t> b(bytes ? row * size_t(h) : 0);
    std::vector<float> f(bytes ? 0 : row * size_t(h));
    // OpenImageIO's rows run top to bottom, Blender's (and ours) bottom to top: read with a negative y stride
    // from the last row.
    void* last_row = bytes ? static_cast<void*>(b.data() + row * size_t(h - 1))
                           : static_cast<void*>(f.data() + row * size_t(h - 1));
    const OIIO::stride_t elem = bytes ? 1 : sizeof(float);
    const bool ok = in->read_image(0, 0, 0, c, bytes ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT, last_row,
                                   OIIO::AutoStride, -OIIO::stride_t(row) * elem, OIIO::AutoStride);
    if (!ok) return missing("could not be decoded (" + in->geterror() + ")");
    return AddImage(name, w, h, c, bytes ? b.data() : nullptr, bytes ? nullptr : f.data(), srgb);
}

}  // namespace sphrect::render
