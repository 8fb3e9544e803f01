"""Reading a ``.sphrect.npz`` scene file defensively (scene.load_scene): before any array is read, every member's
inflated size and its declared .npy shape and dtype are checked against caps and against the mesh arrays' own
counts, so that a small file cannot force gigabytes of allocation; and whatever is malformed -- a corrupted zip,
a plain .npy, JSON that is not an object, a null or non-numeric version, missing or unknown keys, deep nesting --
surfaces as ValueError saying what is wrong.  Pickled objects are refused, never executed (allow_pickle=False,
and object dtypes are rejected from the headers).

Texture paths: a relative path in a scene file is relative to the file's folder, so that a scene renders the same
wherever the process runs (texture_path_to_store, texture_path_loaded)."""
import json
import os
import zipfile
import zlib

import numpy as np

# The largest inflated member, and all members together; the largest scene.json.
MAX_MEMBER_BYTES = 4 << 30
MAX_TOTAL_BYTES = 8 << 30
MAX_JSON_BYTES = 64 << 20

# Mesh arrays: dtype kind ('f' float, 'i' integer) and columns (None: one-dimensional).
MESH_ARRAYS = {"vertices": ("f", 3), "normals": ("f", 3), "triangles": ("i", 3), "material_ids": ("i", None),
               "uvs": ("f", 2), "generated": ("f", 3)}
# A volume's: its closed mesh alone.
VOLUME_ARRAYS = {name: MESH_ARRAYS[name] for name in ("vertices", "triangles")}
# Per-vertex arrays: as many rows as vertices.
PER_VERTEX_ARRAYS = ("normals", "uvs", "generated")

# What the loader may raise on malformed input besides ValueError, all reported as ValueError.
MALFORMED = (KeyError, TypeError, AttributeError, IndexError, RecursionError, zlib.error, zipfile.BadZipFile,
             EOFError, OSError, UnicodeDecodeError, OverflowError, NotImplementedError)


class MalformedScene(ValueError):
    """A scene file that cannot be read: the message names the file and what is wrong."""


def texture_path_to_store(path, scene_path: str) -> str:
    """How a scene file at `scene_path` stores a texture's `path`: a relative one, which the renderer reads from the
    current directory, made relative to the file's folder, so that it names the same file from there; an absolute
    one (or none) as it is."""
    path = os.fspath(path) if path else ""
    if not path or os.path.isabs(path):
        return path
    return os.path.relpath(os.path.abspath(path), os.path.dirname(os.path.abspath(scene_path)))


def texture_path_loaded(scene_path: str, stored, folder: str) -> str:
    """A texture path read from a scene file: a relative one resolved against `folder` (the file's own, or where
    the file was when a copy of it is read) and made absolute, so that it names the same file wherever the process
    runs and the scene is saved again; an absolute one (or none) as it is."""
    if not isinstance(stored, str):
        raise MalformedScene(f"{scene_path}: a texture's path is {stored!r}, not a string")
    if not stored or os.path.isabs(stored):
        return stored
    return os.path.normpath(os.path.join(os.path.abspath(folder), stored))


def member_headers(path):
    """{member name without '.npy': (shape, dtype)} of every array in the archive, read from the .npy headers
    only, each checked against the member's inflated size and the caps."""
    headers, total = {}, 0
    with zipfile.ZipFile(path) as zf:
        for info in zf.infolist():
            if info.file_size > MAX_MEMBER_BYTES:
                raise MalformedScene(f"{path}: member {info.filename} inflates to {info.file_size} bytes, "
                                     f"more than the {MAX_MEMBER_BYTES} a scene file may hold")
            total += info.file_size
            if total > MAX_TOTAL_BYTES:
                raise MalformedScene(f"{path}: members inflate to more than {MAX_TOTAL_BYTES} bytes")
            if not info.filename.endswith(".npy"):
                raise MalformedScene(f"{path}: unexpected member {info.filename}")
            with zf.open(info) as f:
                version = np.lib.format.read_magic(f)
                read = {(1, 0): np.lib.format.read_array_header_1_0,
                        (2, 0): np.lib.format.read_array_header_2_0}.get(version)
                if read is None:
                    raise MalformedScene(f"{path}: member {info.filename} has .npy version {version}")
                shape, _, dtype = read(f)
                header_bytes = f.tell()
            if dtype.hasobject:
                raise MalformedScene(f"{path}: member {info.filename} holds Python objects (refused)")
            count = 1
            for n in shape:
                count *= int(n)
            if count * dtype.itemsize > info.file_size - header_bytes:
                raise MalformedScene(f"{path}: member {info.filename} declares shape {shape} of {dtype}, "
                                     f"more data than its {info.file_size} bytes hold")
            headers[info.filename[:-len(".npy")]] = (tuple(int(n) for n in shape), dtype)
    return headers


def check_mesh_arrays(path, headers, key, what="mesh", arrays=MESH_ARRAYS):
    """The declared shapes of `what` `key`'s arrays (a mesh's MESH_ARRAYS, a volume's VOLUME_ARRAYS): vertices and
    triangles present, each of its dtype kind and columns, normals as many as vertices, material ids as many as
    triangles."""
    shapes = {}
    for name, (kind, columns) in arrays.items():
        header = headers.get(f"{key}.{name}")
        if header is None:
            if name in ("vertices", "triangles"):
                raise MalformedScene(f"{path}: {what} {key} has no {name}")
            continue
        shape, dtype = header
        expected = (shape[0], columns) if columns else (shape[0] if shape else 0,)
        if dtype.kind not in kind or len(shape) != len(expected) or shape != expected:
            want = f"[N, {columns}]" if columns else "[N]"
            raise MalformedScene(f"{path}: {what} {key}.{name} is {dtype} {shape}, not {kind}-typed {want}")
        shapes[name] = shape
    for name in PER_VERTEX_ARRAYS:
        if name in shapes and shapes[name][0] != shapes["vertices"][0]:
            raise MalformedScene(f"{path}: {what} {key} has {shapes[name][0]} {name} for "
                                 f"{shapes['vertices'][0]} vertices")
    if "material_ids" in shapes and shapes["material_ids"][0] != shapes["triangles"][0]:
        raise MalformedScene(f"{path}: {what} {key} has {shapes['material_ids'][0]} material ids for "
                             f"{shapes['triangles'][0]} triangles")


def check_texture_arrays(path, headers, key):
    """The declared shape of texture `key`'s pixels: uint8 or float32 [H, W, C], C in 1..4."""
    header = headers.get(f"{key}.pixels")
    if header is None:
        raise MalformedScene(f"{path}: texture {key} has no pixels")
    shape, dtype = header
    if dtype not in (np.uint8, np.float32) or len(shape) != 3 or not 1 <= shape[2] <= 4:
        raise MalformedScene(f"{path}: texture {key}.pixels is {dtype} {shape}, not uint8 or float32 [H, W, 1..4]")


def read_meta(path, data, headers, format_name, format_version):
    """scene.json as a dict, checked: a JSON object of the format, with an integer version we can read."""
    shape, dtype = headers.get("scene.json", ((), None))
    if dtype is None:
        raise MalformedScene(f"{path}: not a sphrect scene file (no scene.json)")
    if dtype != np.uint8 or len(shape) != 1 or shape[0] > MAX_JSON_BYTES:
        raise MalformedScene(f"{path}: scene.json is {dtype} {shape}, not UTF-8 bytes of at most "
                             f"{MAX_JSON_BYTES}")
    try:
        meta = json.loads(bytes(data["scene.json"]).decode("utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as e:
        raise MalformedScene(f"{path}: scene.json is not valid JSON ({type(e).__name__}: {e})") from None
    if not isinstance(meta, dict):
        raise MalformedScene(f"{path}: scene.json is a JSON {type(meta).__name__}, not an object")
    if meta.get("format") != format_name:
        raise MalformedScene(f"{path}: not a sphrect scene file")
    version = meta.get("version")
    if not isinstance(version, int) or isinstance(version, bool) or version < 1:
        raise MalformedScene(f"{path}: scene format version {version!r} is not a positive integer")
    if version > format_version:
        raise MalformedScene(f"{path}: scene format version {version} is newer than this sphrect "
                             f"({format_version})")
    return meta
