"""Image files read through bpy.data (main thread only), and the cache of the compare mode's reference image.

The reference is read when its path is chosen (the settings' update callback runs on the main thread); a
render in the window runs in a job thread and then only reads the cache."""
import os
import threading

import bpy
import numpy as np


def read_image_rgba(path):
    """float32 RGBA [H, W, 4] of an image file (e.g. an EXR), row 0 = top like sphrect's images. Loads it
    through bpy.data (main thread only) and removes it from there again."""
    img = bpy.data.images.load(path, check_existing=False)
    try:
        width, height = img.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        img.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(img)
    return np.flipud(pixels.reshape(height, width, 4))


_reference_cache = {}  # (absolute path, mtime) -> RGBA [H, W, 4], row 0 = top


def cache_reference_image(path):
    """Read a reference image (EXR) into the cache and return it (main thread only: see above)."""
    path = bpy.path.abspath(path)
    if not path or not os.path.isfile(path):
        raise ValueError(f"reference image '{path}' not found")
    key = (path, os.path.getmtime(path))
    if key not in _reference_cache:
        image = read_image_rgba(path)
        _reference_cache.clear()
        _reference_cache[key] = image
    return _reference_cache[key]


def load_reference_exr(path, width, height):
    """RGBA [H, W, 4] (row 0 = top) of the reference image; ValueError when missing, of another size, or
    not yet read on the main thread."""
    abspath = bpy.path.abspath(path)
    key = (abspath, os.path.getmtime(abspath)) if abspath and os.path.isfile(abspath) else None
    if key in _reference_cache:
        image = _reference_cache[key]
    elif threading.current_thread() is threading.main_thread():
        image = cache_reference_image(path)
    else:
        raise ValueError(f"reference image '{abspath}' missing or changed since it was chosen: choose it again")
    if image.shape[:2] != (height, width):
        raise ValueError(f"reference image is {image.shape[1]}x{image.shape[0]}, the render is {width}x{height}")
    return image
