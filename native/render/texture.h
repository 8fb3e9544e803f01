// Image textures as Cycles 3.4 reads them (kernel/device/cpu/image.h, kernel/svm/image.h): an image of
// bytes or floats, looked up at mapped coordinates with the Image Texture node's interpolation
// (closest: the texel containing the point; linear: bilinear between the four texel centres
// around it) and extension (repeat: wrap; extend: clamp to the edge texel; clip: texels outside
// the image are transparent black), then, for an sRGB image, decoded to linear after filtering
// (Cycles' NODE_IMAGE_COMPRESS_AS_SRGB: byte images keep their stored values and decode per lookup).
// Rows run bottom to top, as in Blender's Image.pixels: v = 0 is the image's bottom edge.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sampling_util.h"

namespace sphrect::render {

struct Rgba {
    float r = 0, g = 0, b = 0, a = 0;
    Rgba operator*(float s) const { return {r * s, g * s, b * s, a * s}; }
    Rgba operator+(const Rgba& o) const { return {r + o.r, g + o.g, b + o.b, a + o.a}; }
    Spectrum rgb() const { return {r, g, b}; }
};

// Cycles' TEX_IMAGE_MISSING_R/G/B/A: what a lookup of an image that could not be loaded returns.
constexpr Rgba kMissingImageColor{1, 0, 1, 1};

enum class TextureInterpolation { kLinear, kClosest };
enum class TextureExtension { kRepeat, kExtend, kClip };

struct Image {
    std::string name;
    int width = 0, height = 0, channels = 0;  // channels 1..4: grey, grey+alpha, RGB, RGBA
    // width x height x channels values, exactly one of the two set: the pixels that `storage` keeps alive.  Scenes
    // that read the same file, or the same read-only array, share one storage instead of each holding a copy.
    const uint8_t* bytes = nullptr;
    const float* floats = nullptr;
    std::shared_ptr<const void> storage;
    bool srgb = false;  // stored values are sRGB-encoded (decoded after filtering)

    // Texel (x, y), both in range, as RGBA in stored units (bytes / 255).
    Rgba Texel(int x, int y) const {
        const size_t i = (size_t(y) * size_t(width) + size_t(x)) * size_t(channels);
        float v[4];
        if (bytes) {
            for (int c = 0; c < channels; ++c) v[c] = bytes[i + c] * (1.0f / 255.0f);
        } else {
            for (int c = 0; c < channels; ++c) v[c] = floats[i + c];
        }
        switch (channels) {
            case 1: return {v[0], v[0], v[0], 1};
            case 2: return {v[0], v[0], v[0], v[1]};
            case 3: return {v[0], v[1], v[2], 1};
            default: return {v[0], v[1], v[2], v[3]};
        }
    }
};

// What an image of that shape takes in memory (bytes: 8-bit values, else floats).
inline uint64_t ImageStorageBytes(int width, int height, int channels, bool bytes) {
    return uint64_t(width) * uint64_t(height) * uint64_t(channels) * (bytes ? 1 : sizeof(float));
}

// The sRGB electro-optical transfer function (IEC 61966-2-1), Cycles' color_srgb_to_linear.
inline float SrgbToLinear(float c) {
    if (c < 0.04045f) return c < 0 ? 0.0f : c * (1.0f / 12.92f);
    return std::pow((c + 0.055f) * (1.0f / 1.055f), 2.4f);
}

inline Rgba DecodeTexel(const Image& im, Rgba c) {
    if (im.srgb) {
        c.r = SrgbToLinear(c.r);
        c.g = SrgbToLinear(c.g);
        c.b = SrgbToLinear(c.b);
    }
    return c;
}

// std::invalid_argument unless an image of that shape can be made.
inline void CheckImageShape(const std::string& name, int width, int height, int channels) {
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
        throw std::invalid_argument("image '" + name + "' must be [H > 0, W > 0, 1..4]");
}

// Non-finite floats become 0, as Cycles' image loader makes them.
inline void ZeroNonFinite(float* values, size_t count) {
    for (size_t i = 0; i < count; ++i)
        if (!std::isfinite(values[i])) values[i] = 0;
}

// An image on pixels that `storage` keeps alive and nobody changes (rows bottom to top; exactly one of bytes and
// floats given, floats all finite): shared, not copied.
inline Image ShareImage(const std::string& name, int width, int height, int channels, const uint8_t* bytes,
                        const float* floats, std::shared_ptr<const void> storage, bool srgb) {
    CheckImageShape(name, width, height, channels);
    if ((bytes == nullptr) == (floats == nullptr))
        throw std::invalid_argument("image '" + name + "': give bytes or floats");
    Image im;
    im.name = name;
    im.width = width;
    im.height = height;
    im.channels = channels;
    im.bytes = bytes;
    im.floats = floats;
    im.storage = std::move(storage);
    im.srgb = srgb;
    return im;
}

// An image of a copy of width x height x channels bytes or floats (exactly one given; rows bottom to top);
// non-finite floats become 0.  std::invalid_argument for a bad shape.
inline Image MakeImage(const std::string& name, int width, int height, int channels, const uint8_t* bytes,
                       const float* floats, bool srgb) {
    CheckImageShape(name, width, height, channels);
    const size_t n = size_t(width) * size_t(height) * size_t(channels);
    if (bytes) {
        auto copy = std::make_shared<std::vector<uint8_t>>(bytes, bytes + n);
        return ShareImage(name, width, height, channels, copy->data(), nullptr, copy, srgb);
    }
    if (!floats) throw std::invalid_argument("image '" + name + "': give bytes or floats");
    auto copy = std::make_shared<std::vector<float>>(floats, floats + n);
    ZeroNonFinite(copy->data(), n);
    return ShareImage(name, width, height, channels, nullptr, copy->data(), copy, srgb);
}

namespace texture_detail {

// Cycles' wrap_periodic / wrap_clamp: a texel index inside [0, size).
inline int WrapRepeat(int x, int size) {
    const int r = x % size;
    return r < 0 ? r + size : r;
}
inline int WrapExtend(int x, int size) { return x < 0 ? 0 : (x >= size ? size - 1 : x); }

// Texel (x, y) under the extension, indices possibly outside the image.
inline Rgba ExtendedTexel(const Image& im, int x, int y, TextureExtension ext) {
    switch (ext) {
        case TextureExtension::kRepeat: return im.Texel(WrapRepeat(x, im.width), WrapRepeat(y, im.height));
        case TextureExtension::kExtend: return im.Texel(WrapExtend(x, im.width), WrapExtend(y, im.height));
        case TextureExtension::kClip:
            if (x < 0 || y < 0 || x >= im.width || y >= im.height) return {};
            return im.Texel(x, y);
    }
    return {};
}

// Floor to int, saturating so that huge or non-finite coordinates stay well defined.
inline int FloorToInt(float x) {
    if (!(x > -1e9f)) return -1000000000;
    if (!(x < 1e9f)) return 1000000000;
    return int(std::floor(x));
}

}  // namespace texture_detail

// The image at (u, v) in [0, 1]^2 per period, filtered and extended, decoded to linear RGB(A).
inline Rgba LookupImage(const Image& im, float u, float v, TextureInterpolation interp, TextureExtension ext) {
    using namespace texture_detail;
    if (im.width <= 0 || im.height <= 0) return kMissingImageColor;
    Rgba c;
    if (interp == TextureInterpolation::kClosest) {
        // Cycles clips closest lookups on the [0, 1] square itself.
        if (ext == TextureExtension::kClip && !(u >= 0 && v >= 0 && u <= 1 && v <= 1)) return {};
        c = ExtendedTexel(im, FloorToInt(u * im.width), FloorToInt(v * im.height), ext);
    } else {
        const float x = u * im.width - 0.5f, y = v * im.height - 0.5f;
        const int ix = FloorToInt(x), iy = FloorToInt(y);
        const float tx = std::isfinite(x) ? x - std::floor(x) : 0.0f, ty = std::isfinite(y) ? y - std::floor(y) : 0.0f;
        c = (ExtendedTexel(im, ix, iy, ext) * (1 - tx) + ExtendedTexel(im, ix + 1, iy, ext) * tx) * (1 - ty) +
            (ExtendedTexel(im, ix, iy + 1, ext) * (1 - tx) + ExtendedTexel(im, ix + 1, iy + 1, ext) * tx) * ty;
    }
    return DecodeTexel(im, c);
}

// Where a material input reads an Image Texture node: which image, at which coordinates (the mesh's
// UVs as (u, v, 0) or its Generated coordinates), mapped by a 3x4 affine transform (the Mapping
// node), and which output (Color, or Alpha).
struct TextureLookup {
    int image = -1;  // into RenderScene::images; -1: no texture
    bool alpha_output = false;
    bool generated = false;  // coordinates 'generated' (MeshData::generated) instead of 'uv'
    float transform[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    TextureInterpolation interpolation = TextureInterpolation::kLinear;
    TextureExtension extension = TextureExtension::kRepeat;

    bool bound() const { return image >= 0; }
};

// The lookup's value at texture coordinates `coords` (before the mapping): its output as RGBA.
inline Rgba EvalTextureLookup(const std::vector<Image>& images, const TextureLookup& t, const Vec3f& coords) {
    const float(&m)[3][4] = t.transform;
    const float u = m[0][0] * coords.x + m[0][1] * coords.y + m[0][2] * coords.z + m[0][3];
    const float v = m[1][0] * coords.x + m[1][1] * coords.y + m[1][2] * coords.z + m[1][3];
    const Rgba c = LookupImage(images[size_t(t.image)], u, v, t.interpolation, t.extension);
    return t.alpha_output ? Rgba{c.a, c.a, c.a, 1} : c;
}

// As a colour input sees it (Alpha as grey) and as a scalar input does (Cycles converts a colour
// to a float by its luminance, linear_rgb_to_gray: Rec.709 in Blender's default configuration).
inline Spectrum TextureColor(const Rgba& c) { return c.rgb(); }
inline float TextureScalar(const Rgba& c) { return Luminance(c.rgb()); }

// The mean decoded colour of an image's texels (the constant an emitter takes of an image on its colour).
inline Spectrum ImageColorMean(const Image& im) {
    double sum[3] = {0, 0, 0};
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const Spectrum c = TextureColor(DecodeTexel(im, im.Texel(x, y)));
            sum[0] += c.x, sum[1] += c.y, sum[2] += c.z;
        }
    const double n = double(im.width) * im.height;
    return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)};
}

// The mean over the image's texels of what a scalar input reads there (its Color output's luminance, or its
// Alpha), each clamped to [0, 1] as a Mix factor is: the constant the exporter puts where a factor cannot vary.
inline double ImageScalarMean(const Image& im, bool alpha_output) {
    double sum = 0;
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const Rgba c = DecodeTexel(im, im.Texel(x, y));
            sum += std::clamp(alpha_output ? c.a : TextureScalar(c), 0.0f, 1.0f);
        }
    return sum / (double(im.width) * im.height);
}

}  // namespace sphrect::render
