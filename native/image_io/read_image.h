// The C interface of the OpenImageIO reader module (libsphrect_image_io.so, loaded on first use by
// RenderScene::LoadImage).  A module of its own because OpenImageIO pulls in some 250 shared libraries: linked
// into _native, they cost every `import sphrect` half a second, scenes without image files included.
#pragma once

#include <cstddef>

extern "C" {

// An image read from a file: width x height x channels (1..4) values, rows bottom to top, bytes (uint8) when the
// file stores 8-bit values, else floats.  pixels is malloc'ed: free it with sphrect_free_image_pixels.
struct SphrectImagePixels {
    int width, height, channels;
    int bytes;  // 1: uint8 values, 0: float values
    void* pixels;
};

// 1 on success; 0 with a message in error[0 .. error_size) otherwise.
typedef int (*SphrectReadImageFn)(const char* path, SphrectImagePixels* out, char* error, size_t error_size);
typedef void (*SphrectFreeImagePixelsFn)(void* pixels);
__attribute__((visibility("default"))) int sphrect_read_image(const char* path, SphrectImagePixels* out, char* error,
                                                              size_t error_size);
__attribute__((visibility("default"))) void sphrect_free_image_pixels(void* pixels);
}
