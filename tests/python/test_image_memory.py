"""Image textures under the memory limit (issue 27, class 4): a texture counts against a Renderer's memory_limit
before it is decoded or copied, a file is decoded once into the memory the scene keeps, and renderers of one scene
share the pixels of a file (unchanged since) or of a read-only array instead of each holding a copy.  Memory is
read from the child process's own resident-set figures (/proc/self/status), so each case runs in a fresh process;
the margins are several times the noise of those figures (a few MB): deterministic, no false failures seen."""
import os
import struct
import subprocess
import sys
import zlib

import numpy as np
import pytest

import sphrect
from test_render_textures import LOOKUP, lit_scene, render

MB = 1 << 20


def write_png(path, width, height, channels=1, bits=8, row=None):
    """A PNG of `height` equal rows (`row`: bytes of one row, zeros by default), written a row at a time, so that
    a 32768 x 32768 file costs no memory to make.  channels 1 (grey) or 4 (RGBA)."""
    colour_type = {1: 0, 4: 6}[channels]
    row = row if row is not None else bytes((width * channels * bits + 7) // 8)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    compressor = zlib.compressobj(1)
    data = b"".join(compressor.compress(b"\0" + row) for _ in range(height)) + compressor.flush()
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bits, colour_type, 0, 0, 0)))
        f.write(chunk(b"IDAT", data))
        f.write(chunk(b"IEND", b""))


def run_child(code, timeout=300):
    """Runs `code` in a fresh interpreter with this file's helpers; its stdout's last line, evaluated."""
    prelude = (f"import sys, numpy as np, sphrect\nsys.path.insert(0, {os.path.dirname(__file__)!r})\n"
               "from test_image_memory import *\n")
    run = subprocess.run([sys.executable, "-c", prelude + code], capture_output=True, text=True, timeout=timeout)
    assert run.returncode == 0, run.stderr[-3000:]
    return eval(run.stdout.strip().splitlines()[-1])


def resident():
    """(current, peak) resident memory of this process, in bytes."""
    fields = dict(line.split(":", 1) for line in open("/proc/self/status"))
    return int(fields["VmRSS"].split()[0]) * 1024, int(fields["VmHWM"].split()[0]) * 1024


def textured(*textures):
    return lit_scene(sphrect.Material(textures={"base_color": LOOKUP}), list(textures), width=8, height=8)


@pytest.fixture(scope="module")
def huge_png(tmp_path_factory):
    """32768 x 32768 grey, 1 bit a pixel: 128 KB on disk, 1 GiB decoded (the reader gives a byte a pixel)."""
    path = tmp_path_factory.mktemp("huge") / "huge.png"
    write_png(path, 32768, 32768, bits=1)
    return str(path)


def test_a_huge_image_file_is_refused_before_it_is_decoded(huge_png):
    # Before: decoded whole (1 GiB, held twice while copied) and rendered, whatever memory_limit said.
    error, peak = run_child(f"""
try:
    sphrect.Renderer(textured(sphrect.Texture(name="huge", path={huge_png!r})), memory_limit=100 * 2**20)
    error = None
except ValueError as e:
    error = str(e)
print((error, resident()[1]))
""")
    assert error is not None and "image 'huge'" in error and "takes 1.00 GiB" in error and "memory_limit" in error
    assert peak < 400 * MB  # the interpreter, numpy and the module: ~100 MB; decoding it would take 1 GiB more


def test_a_huge_pixel_array_is_refused_before_it_is_copied():
    pixels = np.zeros((8192, 8192, 4), np.uint8)  # 256 MiB
    with pytest.raises(ValueError, match=r"image 'big' takes 0.25 GiB.*raise memory_limit"):
        sphrect.Renderer(textured(sphrect.Texture(name="big", pixels=pixels)), memory_limit=100 * MB)
    sphrect.Renderer(textured(sphrect.Texture(name="small", pixels=pixels[:2048])), memory_limit=100 * MB)


def test_the_film_and_the_textures_share_one_limit():
    film = sphrect.render_memory_bytes(1, 8, 8)
    pixels = np.zeros((1024, 1024, 4), np.uint8)  # 4 MiB
    sphrect.Renderer(textured(sphrect.Texture(pixels=pixels)), techniques="rectangle", memory_limit=film + 4 * MB)
    with pytest.raises(ValueError, match="memory limit"):
        sphrect.Renderer(textured(sphrect.Texture(pixels=pixels)), techniques="rectangle",
                         memory_limit=film + 4 * MB - 1)
    with pytest.raises(ValueError, match="image 'image' takes .* the memory limit leaves beside the film"):
        sphrect.Renderer(textured(sphrect.Texture(pixels=pixels)), techniques="rectangle", memory_limit=film)


def test_a_file_is_decoded_once_into_the_memory_the_scene_keeps(tmp_path):
    # 4096 x 4096 RGBA bytes: 64 MiB decoded.  Before: decoded into the reader's buffer, then copied (128 MiB peak).
    path, tiny = tmp_path / "rgba.png", tmp_path / "tiny.png"
    write_png(path, 4096, 4096, channels=4, row=bytes(range(256)) * 64)
    write_png(tiny, 1, 1)
    grown, peak_grown = run_child(f"""
scene = textured(sphrect.Texture(path={str(path)!r}))
sphrect.Renderer(textured(sphrect.Texture(path={str(tiny)!r})))  # loads OpenImageIO (~100 MB of libraries)
before = resident()
r = sphrect.Renderer(scene)
after = resident()
print((after[0] - before[0], after[1] - before[0]))
""")
    assert 60 * MB < grown < 80 * MB
    assert peak_grown < 96 * MB


def test_renderers_of_one_scene_share_its_image_file(tmp_path):
    # The add-on's compare mode makes up to 20 renderers of one scene: before, each decoded its own copy.
    path = tmp_path / "rgba.png"
    write_png(path, 4096, 4096, channels=4, row=bytes(range(256)) * 64)
    grown = run_child(f"""
scene = textured(sphrect.Texture(path={str(path)!r}))
first = sphrect.Renderer(scene)
before = resident()[0]
others = [sphrect.Renderer(scene) for _ in range(8)]
print(resident()[0] - before)
""")
    assert grown < 32 * MB  # 8 more copies would be 512 MiB


def test_renderers_share_a_read_only_array_and_copy_a_writable_one():
    grown = run_child("""
pixels = (np.arange(4096 * 4096 * 4) % 251).astype(np.uint8).reshape(4096, 4096, 4)
results = []
for writeable in (False, True):
    pixels.flags.writeable = writeable
    scene = textured(sphrect.Texture(pixels=pixels))
    first = sphrect.Renderer(scene)
    before = resident()[0]
    others = [sphrect.Renderer(scene) for _ in range(4)]
    results.append(resident()[0] - before)
    del first, others
print(tuple(results))
""")
    shared, copied = grown
    assert shared < 16 * MB and copied > 4 * 60 * MB


def test_a_writable_array_changed_after_the_renderer_is_made_does_not_change_its_image():
    pixels = np.full((2, 2, 3), 0.25, np.float32)
    r = sphrect.Renderer(textured(sphrect.Texture(pixels=pixels)), techniques="rectangle", seed=3)
    pixels[:] = 1.0
    r.render(4)
    same = render(textured(sphrect.Texture(pixels=np.full((2, 2, 3), 0.25, np.float32))), spp=4)
    np.testing.assert_array_equal(r.image("rectangle")[..., :3], same)


def test_a_file_changed_since_another_renderer_read_it_is_read_again(tmp_path):
    path = tmp_path / "grey.png"
    write_png(path, 4, 4, row=bytes([64] * 4))
    dark = sphrect.Renderer(textured(sphrect.Texture(path=str(path), colorspace="linear")))
    write_png(path, 4, 4, row=bytes([255] * 4))
    os.utime(path, ns=(0, os.stat(path).st_mtime_ns + 10 ** 9))
    dark.render(2)
    bright = render(textured(sphrect.Texture(path=str(path), colorspace="linear")), spp=2)
    expected = render(textured(sphrect.Texture(pixels=np.full((4, 4, 1), 255, np.uint8), colorspace="linear")),
                      spp=2)
    np.testing.assert_array_equal(bright, expected)
    assert dark.image()[..., :3].mean() < 0.5 * bright.mean()
