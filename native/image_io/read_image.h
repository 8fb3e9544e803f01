// The C interface of the OpenImageIO reader module (libsphrect_image_io.so, loaded on first use by
// RenderScene::LoadImage).  A module of its own because OpenImageIO pulls in some 250 shared libraries: linked
// into _native, they cost every `import sphrect` half a second, scenes without image files included.
#pragma once

#include <cstddef>

extern "C" {

// An image read from a file: width x height x channels (1..4) values, rows bottom to top, bytes (uint8) when the
// file stores 8-bit values, else floats, in the room the caller's allocate gave.
struct SphrectImagePixels {
    int width, height, channels;
    int bytes;  // 1: uint8 values, 0: float values
    void* pixels;
};

// Called once the file's header is read, before anything is decoded: room for width x height x channels values
// (bytes: uint8, else float) that the caller owns, or nullptr to refuse the image, with why in error[0 ..
// error_size).  So an image is checked against a memory limit before it is decoded, and decoded once, in place.
typedef void* (*SphrectImageAllocateFn)(void* context, int width, int height, int channels, int bytes, char* error,
                                        size_t error_size);

// 1 on success; 0 with a message in error[0 .. error_size) otherwise (the caller still owns what allocate gave).
typedef int (*SphrectReadImageFn)(const char* path, SphrectImageAllocateFn allocate, void* context,
                                  SphrectImagePixels* out, char* error, size_t error_size);
__attribute__((visibility("default"))) int sphrect_read_image(const char* path, SphrectImageAllocateFn allocate,
                                                              void* context, SphrectImagePixels* out, char* error,
                                                              size_t error_size);
}
