"""Object volumes -> sphrect.Volume: one per object instance and material slot whose material has a volume
(materials.volume_socket), that slot's triangles in world space, wound as Blender's (mirrored by a negative scale:
reversed, so that they face out), whatever the material's surface (a volume-only material's surface is left out of
the meshes: materials.left_out_surface).  The medium is read by volume_shaders.read_volume, once per material unless
an input varies in space (then at the centre of the slot's bounding box, per instance)."""
import numpy as np

from .geometry import LocalMesh, slot_triangles, to_world
from .log import ExportLog
from .materials import volume_socket
from .volume_shaders import VolumePoint, read_volume
from .visibility import invisible_to


def _open_edges(triangles):
    """How many edges of the triangles are not shared by exactly two of them (0: a closed mesh)."""
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int(np.count_nonzero(counts != 2))


def _smoke_density(obj):
    """A smoke domain's mean density at this frame (its evaluated grid: 0 where nothing is simulated or cached), or
    None for an object that is no smoke domain."""
    for m in getattr(obj, "modifiers", ()):
        if m.type == "FLUID" and m.fluid_type == "DOMAIN":
            grid = m.domain_settings.density_grid
            values = np.empty(len(grid), np.float32)
            if len(grid):
                grid.foreach_get(values)
            return float(values.mean()) if len(values) else 0.0
    return None


def _reads_density_grid(mat):
    """Whether the material's Principled Volume multiplies its Density by the domain's density grid, as Cycles 3.4
    does through its Density Attribute."""
    return mat.node_tree is not None and any(
        n.bl_idname == "ShaderNodeVolumePrincipled" and n.inputs["Density Attribute"].default_value == "density"
        for n in mat.node_tree.nodes)


class VolumeExport:
    """The scene's object volumes (`list`, sphrect.Volume), added per depsgraph instance (add_instance)."""

    def __init__(self, sphrect, log):
        self.sphrect, self.log = sphrect, log
        self.list = []
        self._media = {}  # material -> (its medium, the warnings reading it gave) where it does not vary in space
        self._slots = {}  # (object, data) -> [(material, LocalMesh of the slot's triangles, texture space)]

    def _volume_slots(self, obj, key):
        if key not in self._slots:
            slots = [(i, s.material) for i, s in enumerate(obj.material_slots) if volume_socket(s.material)]
            found = []
            mesh = slot_triangles(obj) if slots else None
            if mesh is not None:
                vertices, triangles, material_index, texspace = mesh
                material_index = np.clip(material_index, 0, len(obj.material_slots) - 1)
                for i, mat in slots:
                    tris = triangles[material_index == i]
                    if not len(tris):
                        continue
                    used, compact = np.unique(tris, return_inverse=True)
                    local = LocalMesh(vertices[used], compact.reshape(-1, 3).astype(np.int32), None, None)
                    if _open_edges(local.triangles):
                        self.log.unsupported_feature("volume meshes that are not closed (exported as they are: "
                                                     "rays through an open edge miss the boundary)", obj.name)
                    found.append((mat, local, texspace))
            self._slots[key] = found
        return self._slots[key]

    def add_instance(self, obj, inst, name):
        """The volumes of a depsgraph instance of mesh object `obj` (named `name` in the scene)."""
        slots = self._volume_slots(obj, (obj.name_full, obj.data.name_full))
        if not slots:
            return
        matrix = np.array(inst.matrix_world, dtype=np.float64)
        if not np.isfinite(matrix).all():
            return  # the surface export says so
        if invisible_to(obj, self.sphrect.scene.RAY_KINDS, inst.parent if inst.is_instance else None):
            self.log.unsupported_feature("Ray Visibility of object volumes (seen by every ray)", obj.name)
        smoke = _smoke_density(obj)
        for mat, local, texspace in slots:
            world = to_world(local, matrix)
            if world is None:
                continue
            vertices, triangles, _ = world
            grid = smoke is not None and _reads_density_grid(mat)
            if grid and smoke == 0:
                continue  # an empty grid (nothing simulated or cached at this frame) is no volume, as Cycles shows it
            medium = self._medium(mat, obj.name, local, texspace, matrix)
            if medium is not None and grid:
                self.log.unsupported_feature(f"heterogeneous volume density (a smoke domain's grid): its mean, "
                                             f"{smoke:.3g}, times the material's density used throughout the domain",
                                             obj.name)
                medium = self.sphrect.Medium(sigma_s=tuple(smoke * x for x in medium.sigma_s),
                                             sigma_a=tuple(smoke * x for x in medium.sigma_a), g=medium.g)
            if medium is None:
                continue
            label = name if len(slots) == 1 else f"{name}/{mat.name}"
            self.list.append(self.sphrect.Volume(vertices=vertices, triangles=triangles, medium=medium, name=label))

    def _medium(self, mat, owner, local, texspace, matrix):
        """The slot's medium, read once per material unless an input varies in space (then at the centre of the
        slot's bounding box); the warnings of reading it name every object using it."""
        cached = self._media.get(mat.name_full)
        if cached is None:
            centre = 0.5 * (local.vertices.min(axis=0) + local.vertices.max(axis=0)).astype(np.float64)
            location, size = texspace
            generated = np.divide(centre - (location - size), 2.0 * size, out=np.full(3, 0.5), where=size != 0)
            point = VolumePoint(position=tuple(matrix[:3, :3] @ centre + matrix[:3, 3]), object=tuple(centre),
                                generated=tuple(generated))
            log = ExportLog()
            medium, varies = read_volume(self.sphrect, volume_socket(mat), "", log, point)
            cached = (medium, list(log.unsupported), log.problems)
            if not varies:
                self._media[mat.name_full] = cached
        medium, warnings, problems = cached
        for what in warnings:
            self.log.unsupported_feature(what, owner)
        for text in problems:
            self.log.problem(text)
        return medium
