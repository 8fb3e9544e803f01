"""Evaluated depsgraph -> sphrect.Scene.

    scene, log = scene_from_depsgraph(depsgraph)   # log.warning_text(): what was not supported
    export_scene(depsgraph_or_scene, path)         # the standalone scene file (sphrect.save_scene)
"""
import numpy as np

from ...native import load_sphrect
from .camera import export_camera
from .geometry import MESH_LIKE, is_mesh_data, render_uv_layer, shadow_terminator_offset, to_world, triangulate
from .lights import export_light
from .log import ExportLog
from .materials import export_material, export_world
from .node_program import program_globals
from .textures import TextureExport, coordinates_needed, has_normal_map, is_anisotropic, programs_of
from .visibility import invisible_to, warn_unhonoured
from .volumes import VolumeExport


class _Materials:
    """Blender materials -> indices into Scene.materials (index 0: the default for empty slots), and the images
    they read -> Scene.textures."""

    def __init__(self, sphrect, log):
        self.sphrect, self.log = sphrect, log
        self.textures = TextureExport(sphrect, log)
        self.list = [sphrect.Material(name="default")]
        self.coordinates = [set()]  # per material: the mesh coordinates it reads (textures.coordinates_needed)
        self.attributes = [set()]  # per material: the mesh attributes its programs read (NodeProgram.attributes)
        self.object_info = [False]  # per material: whether its programs read Object Info
        self.index = {}

    def id_of(self, mat):
        if mat is None:
            return 0
        key = mat.name_full
        if key not in self.index:
            self.index[key] = len(self.list)
            self.list.append(export_material(self.sphrect, mat, self.log, self.textures))
            warn_unhonoured(self.log, material=mat, exported=self.list[-1])
            self.coordinates.append(coordinates_needed(self.list[-1]))
            programs = programs_of(self.list[-1])
            self.attributes.append(set().union(*(p.attributes for p in programs)))
            self.object_info.append(any(g.startswith("object_") and g not in ("object_normal",)
                                        for p in programs for g in program_globals(self.sphrect, p)))
        return self.index[key]

    def slot_ids(self, obj):
        slots = [self.id_of(s.material) for s in obj.material_slots]
        return np.array(slots or [0], dtype=np.int32)

    def coordinates_of(self, obj, slots):
        """The coordinates the object's materials read; UV Map / Normal Map nodes naming another UV map than the
        object's render one are warned (that one is used)."""
        needed = set().union(*(self.coordinates[i] for i in slots))
        if "uv" in needed and obj.type == "MESH":
            layer = render_uv_layer(obj.data)
            named = set().union(*(self.textures.uv_maps_named.get(self.list[i].name, set()) for i in slots))
            for uv_map in sorted(named - {layer.name if layer is not None else ""}):
                self.log.unsupported_feature(f"UV map '{uv_map}' named by a node, not the render UV map (that "
                                             "one used)", obj.name)
        return needed


def _object_info(sphrect, obj, inst):
    """sphrect.Mesh's Object Info fields of a depsgraph instance, as Cycles syncs them (blender/object.cpp): the
    object's colour and pass index, its random number from the instance's random_id, or for an object that is no
    instance from its name (Cycles' hash_uint2(hash_string(name), 0))."""
    random = sphrect._native._object_random(obj.name, inst.random_id if inst.is_instance else None)
    return {"object_color": tuple(float(x) for x in obj.color), "object_index": int(obj.pass_index),
            "object_random": float(random)}


def rendered_world(depsgraph):
    """The world Cycles 3.4 renders for the depsgraph's view layer: none (black, lighting nothing) when the view
    layer's Filter > Environment is off (Cycles' sync_view_layer: use_sky, the background shader then empty)."""
    view_layer = getattr(depsgraph, "view_layer", None)
    if view_layer is not None and not view_layer.use_sky:
        return None
    scene = depsgraph.scene_eval if hasattr(depsgraph, "scene_eval") else depsgraph.scene
    return scene.world


def scene_from_depsgraph(depsgraph):
    """(sphrect.Scene, ExportLog) for an evaluated depsgraph (render or viewport)."""
    sphrect = load_sphrect()
    log = ExportLog()
    bl_scene = depsgraph.scene_eval if hasattr(depsgraph, "scene_eval") else depsgraph.scene
    scene = sphrect.Scene()
    cam = bl_scene.camera.evaluated_get(depsgraph) if bl_scene.camera is not None else None
    scene.camera = export_camera(sphrect, bl_scene, cam, log)
    materials = _Materials(sphrect, log)
    world = rendered_world(depsgraph)
    scene.world = export_world(sphrect, world, log, materials.textures)
    warn_unhonoured(log, world=world, exported=scene.world)
    volumes = VolumeExport(sphrect, log)
    cache = {}
    skipped_types = set()
    for inst in depsgraph.object_instances:
        if not inst.show_self:
            continue  # an instancer (a particle emitter) hidden from render: Cycles skips its own geometry too
        obj = inst.object
        name = obj.name if not inst.is_instance else f"{inst.parent.name}/{obj.name}#{inst.random_id & 0xffff}"
        if obj.type == "LIGHT":
            light = export_light(sphrect, obj, inst.matrix_world, name, log, inst.parent if inst.is_instance else None,
                                 materials.textures)
            if light is not None:
                scene.lights.append(light)
            continue
        if obj.type not in MESH_LIKE:
            if obj.type not in {"CAMERA", "EMPTY", "ARMATURE", "LATTICE", "SPEAKER", "LIGHT_PROBE"}:
                skipped_types.add(obj.type)
                log.unsupported_feature(f"{obj.type.lower()} objects", obj.name)
            continue
        if not is_mesh_data(obj.data):
            continue  # a curve, text, surface or metaball: its mesh comes as an instance of its own (Cycles' rule)
        for psys in getattr(obj, "particle_systems", ()):
            if psys.settings.type == "HAIR" and psys.settings.render_type == "PATH":
                log.unsupported_feature("hair particles", obj.name)
        volumes.add_instance(obj, inst, name)
        key = (obj.name_full, obj.data.name_full if obj.data is not None else "")
        if key not in cache:  # instances share the triangulation and the material ids
            slots = materials.slot_ids(obj)
            needed = materials.coordinates_of(obj, slots)
            attributes = set().union(*(materials.attributes[i] for i in slots))
            local = triangulate(obj, log, uvs="uv" in needed, generated="generated" in needed, attributes=attributes)
            if local is not None:
                object_space = any(has_normal_map(materials.list[i]) or is_anisotropic(materials.list[i])
                                   or programs_of(materials.list[i]) for i in slots)
                object_info = any(materials.object_info[i] for i in slots)
                cache[key] = (local, slots[np.clip(local.material_index, 0, len(slots) - 1)], object_space,
                              object_info)
            else:
                cache[key] = None
        if cache[key] is None:
            continue
        local, material_ids, object_space, object_info = cache[key]
        if not np.isfinite(np.array(inst.matrix_world)).all():
            log.problem(f"object '{name}' has a transform that is not finite (NaN or infinite): skipped")
            continue
        world = to_world(local, inst.matrix_world)
        if world is None:
            log.problem(f"object '{name}' has zero scale: skipped")
            continue
        vertices, triangles, normals = world
        # Normal maps and the default tangent apply in the object's space (Cycles): the renderer needs its linear map.
        object_linear = np.array(inst.matrix_world)[:3, :3].tolist() if object_space else None
        # Node programs' Object coordinates undo the whole transform.
        object_translation = tuple(float(x) for x in np.array(inst.matrix_world)[:3, 3]) if object_space else None
        scene.meshes.append(sphrect.Mesh(vertices=vertices, triangles=triangles, normals=normals,
                                         material_ids=material_ids, name=name, uvs=local.uvs,
                                         generated=local.generated, object_linear=object_linear,
                                         object_translation=object_translation,
                                         invisible_to=invisible_to(obj, sphrect.scene.RAY_KINDS,
                                                                      inst.parent if inst.is_instance else None),
                                         shadow_terminator_offset=shadow_terminator_offset(obj, normals, log),
                                         attributes=local.attributes, attributes_fac_x=local.attributes_fac_x,
                                         corners_reversed=bool(np.linalg.det(np.array(inst.matrix_world)[:3, :3]) < 0),
                                         **(_object_info(sphrect, obj, inst) if object_info else {})))
    scene.materials = materials.list
    scene.textures = materials.textures.list
    scene.volumes = volumes.list
    emissive = {i for i, m in enumerate(scene.materials) if any(c > 0 for c in m.emission)}
    lit_by_meshes = any(np.isin(m.material_ids, list(emissive)).any() for m in scene.meshes) if emissive else False
    if not scene.lights and not lit_by_meshes and not any(c > 0 for c in scene.world.background) \
            and scene.world.environment is None:
        log.problem("the scene has no lights: the image will be black")
    return scene, log


def export_scene(depsgraph_or_scene, path):
    """Write the standalone scene file (`sphrect.save_scene` format; load it with `sphrect.load_scene`).
    Accepts an evaluated depsgraph or a bpy Scene (its view layer's depsgraph is evaluated for rendering
    settings as shown in the viewport). Returns the ExportLog."""
    import bpy
    depsgraph = depsgraph_or_scene
    if isinstance(depsgraph_or_scene, bpy.types.Scene):
        depsgraph = depsgraph_or_scene.view_layers[0].depsgraph
        depsgraph.update()
    scene, log = scene_from_depsgraph(depsgraph)
    load_sphrect().save_scene(scene, path)
    return log
