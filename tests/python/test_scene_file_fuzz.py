"""The scene loader under malformed files (issue 15): every broken file is ValueError saying what is wrong, never
another exception, and a small file cannot make it allocate gigabytes (shapes and sizes are checked from the
headers first).  A fuzz corpus with a fixed seed (truncations, flipped bytes, swapped members) and hand-made
cases; pickled objects are refused."""
import io
import json
import os
import zipfile

import numpy as np
import pytest

import sphrect
from sphrect import scene_file


def valid_scene_bytes(tmp_path):
    cam = sphrect.Camera(width=8, height=6)
    mesh = sphrect.Mesh(vertices=np.random.default_rng(0).random((40, 3), np.float32),
                        triangles=np.arange(60, dtype=np.int32).reshape(20, 3) % 40,
                        material_ids=np.zeros(20, np.int32))
    scene = sphrect.Scene(camera=cam, meshes=[mesh],
                          lights=[sphrect.RectLight(corner=(0, 0, 1), edge_x=(1, 0, 0), edge_y=(0, 1, 0),
                                                    radiance=(1, 1, 1))])
    path = tmp_path / "valid.sphrect.npz"
    sphrect.save_scene(scene, str(path))
    return path.read_bytes()


def npz(members, path):
    """An archive of {name: array or raw bytes} (raw bytes stored as the .npy member as they are)."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, value in members.items():
            if isinstance(value, bytes):
                zf.writestr(name + ".npy", value)
            else:
                buf = io.BytesIO()
                np.save(buf, value, allow_pickle=True)
                zf.writestr(name + ".npy", buf.getvalue())
    return str(path)


def meta_bytes(meta):
    return np.frombuffer(json.dumps(meta).encode("utf-8"), np.uint8)


def good_meta():
    return {"format": "sphrect-scene", "version": 5, "camera": {}, "world": {}, "materials": [], "lights": [],
            "meshes": [{"name": "m", "arrays": "mesh0"}]}


def good_arrays():
    return {"mesh0.vertices": np.zeros((3, 3), np.float32), "mesh0.triangles": np.array([[0, 1, 2]], np.int32)}


def expect_value_error(path):
    with pytest.raises(ValueError) as info:
        sphrect.load_scene(path)
    assert str(path) in str(info.value)  # the message names the file
    return str(info.value)


def test_the_reference_cases_load(tmp_path):
    path = tmp_path / "ok.sphrect.npz"
    path.write_bytes(valid_scene_bytes(tmp_path))
    assert len(sphrect.load_scene(str(path)).meshes[0].triangles) == 20
    assert sphrect.load_scene(npz({"scene.json": meta_bytes(good_meta()), **good_arrays()}, tmp_path / "m.npz"))


def test_fuzz_corpus_of_broken_files(tmp_path):
    """300 files from a fixed seed: truncated, bytes flipped, members dropped or duplicated.  Each either loads
    (a flip that changes nothing checked) or raises ValueError; no other exception."""
    good = valid_scene_bytes(tmp_path)
    rng = np.random.default_rng(20261201)
    outcomes = {"loaded": 0, "refused": 0}
    for k in range(300):
        data = bytearray(good)
        mode = k % 3
        if mode == 0:
            data = data[:int(rng.integers(0, len(data)))]
        elif mode == 1:
            for _ in range(int(rng.integers(1, 8))):
                data[int(rng.integers(0, len(data)))] ^= int(rng.integers(1, 256))
        else:
            cut = int(rng.integers(0, len(data)))
            data = data[:cut] + bytes(rng.integers(0, 256, int(rng.integers(1, 64)), dtype=np.uint8)) + data[cut:]
        path = tmp_path / f"fuzz{k}.npz"
        path.write_bytes(bytes(data))
        try:
            sphrect.load_scene(str(path))
            outcomes["loaded"] += 1
        except ValueError:
            outcomes["refused"] += 1
    assert outcomes["refused"] > 200, outcomes


@pytest.mark.parametrize("case", [
    "plain npy", "not a zip", "json list", "json null version", "json string version", "json bool version",
    "json float version", "json newer version", "json missing camera", "json unknown camera key",
    "json unknown light type", "json deep nesting", "json not utf8", "json not json", "json as floats",
    "no scene.json", "mesh without triangles", "vertices of 2 columns", "triangles as floats",
    "normals count", "material ids count", "object array", "mesh arrays key not a string",
])
def test_malformed_files_are_value_errors(tmp_path, case):
    meta, arrays = good_meta(), good_arrays()
    path = tmp_path / "bad.npz"
    if case == "plain npy":
        np.save(path.with_suffix(".npy"), np.zeros(4))
        os.replace(path.with_suffix(".npy"), path)
        expect_value_error(str(path))
        return
    if case == "not a zip":
        path.write_bytes(b"PK\x03\x04 this is no archive")
        expect_value_error(str(path))
        return
    members = {"scene.json": meta_bytes(meta), **arrays}
    if case == "json list":
        members["scene.json"] = meta_bytes([meta])
    elif case.startswith("json") and "version" in case:
        meta["version"] = {"json null version": None, "json string version": "5", "json bool version": True,
                           "json float version": 5.0, "json newer version": 99}[case]
        members["scene.json"] = meta_bytes(meta)
    elif case == "json missing camera":
        del meta["camera"]
        members["scene.json"] = meta_bytes(meta)
    elif case == "json unknown camera key":
        meta["camera"] = {"zoom": 3}
        members["scene.json"] = meta_bytes(meta)
    elif case == "json unknown light type":
        meta["lights"] = [{"type": "laser"}]
        members["scene.json"] = meta_bytes(meta)
    elif case == "json deep nesting":
        members["scene.json"] = np.frombuffer(("[" * 100000 + "]" * 100000).encode(), np.uint8)
    elif case == "json not utf8":
        members["scene.json"] = np.frombuffer(b"\xff\xfe\x00{", np.uint8)
    elif case == "json not json":
        members["scene.json"] = np.frombuffer(b"{format: sphrect", np.uint8)
    elif case == "json as floats":
        members["scene.json"] = np.zeros(8)
    elif case == "no scene.json":
        del members["scene.json"]
    elif case == "mesh without triangles":
        del members["mesh0.triangles"]
    elif case == "vertices of 2 columns":
        members["mesh0.vertices"] = np.zeros((3, 2), np.float32)
    elif case == "triangles as floats":
        members["mesh0.triangles"] = np.zeros((1, 3), np.float32)
    elif case == "normals count":
        members["mesh0.normals"] = np.zeros((4, 3), np.float32)
    elif case == "material ids count":
        members["mesh0.material_ids"] = np.zeros(2, np.int32)
    elif case == "object array":
        members["mesh0.vertices"] = np.array([object()] * 3)
    elif case == "mesh arrays key not a string":
        meta["meshes"] = [{"name": "m", "arrays": ["mesh0"]}]
        members["scene.json"] = meta_bytes(meta)
    message = expect_value_error(npz(members, path))
    if case == "object array":
        assert "objects" in message or "pickle" in message.lower()


def npy_header(shape, dtype="<f4"):
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": dtype, "fortran_order": False, "shape": shape})
    return buf.getvalue()


def test_a_header_declaring_a_trillion_rows_is_refused_before_reading(tmp_path):
    members = {"scene.json": meta_bytes(good_meta()), **good_arrays()}
    members["mesh0.vertices"] = npy_header((10 ** 12, 3)) + b"\0" * 36  # declares 12 TB, holds 36 bytes
    message = expect_value_error(npz(members, tmp_path / "trillion.npz"))
    assert "declares shape" in message


def test_a_member_inflating_beyond_the_cap_is_refused(tmp_path, monkeypatch):
    """The cap is lowered to 1 MiB so that the bomb stays small: 4 MiB of zeros compress to ~4 KiB."""
    monkeypatch.setattr(scene_file, "MAX_MEMBER_BYTES", 1 << 20)
    members = {"scene.json": meta_bytes(good_meta()), **good_arrays()}
    members["mesh0.vertices"] = np.zeros(((4 << 20) // 12, 3), np.float32)
    path = npz(members, tmp_path / "bomb.npz")
    assert os.path.getsize(path) < 64 << 10
    message = expect_value_error(path)
    assert "inflates to" in message
