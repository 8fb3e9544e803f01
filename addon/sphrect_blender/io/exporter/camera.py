"""Blender camera -> sphrect.Camera (Blender's model: looks down local -Z, +Y up), with the scene's film settings."""
import numpy as np

from ...names import sphrect_name


def render_resolution(render):
    pct = render.resolution_percentage / 100.0
    return max(1, int(render.resolution_x * pct)), max(1, int(render.resolution_y * pct))


def rigid_matrix(matrix_world):
    """4x4 numpy matrix with the scale removed from the rotation columns (cameras ignore object scale)."""
    m = np.array(matrix_world, dtype=np.float64)
    for i in range(3):
        n = np.linalg.norm(m[:3, i])
        if n > 0:
            m[:3, i] /= n
    return m


def film_settings(bl_scene):
    """Camera fields of the film: Film > Transparent, and the SPHRECT Film panel's pixel filter, a box always 1 pixel
    wide as Cycles 3.4 renders it (whatever its Width says), so that the image is Cycles' at edges too."""
    settings = bl_scene.original.sphrect  # as the engine's settings: an add-on property change does not re-evaluate
    pixel_filter = sphrect_name(settings.pixel_filter)
    width = 1.0 if pixel_filter == "box" else float(settings.filter_width)
    return dict(film_transparent=bool(bl_scene.render.film_transparent), pixel_filter=pixel_filter, filter_width=width)


def export_camera(sphrect, bl_scene, cam_obj, log):
    width, height = render_resolution(bl_scene.render)
    render = bl_scene.render
    if abs(render.pixel_aspect_x - render.pixel_aspect_y) > 1e-6:
        log.unsupported_feature("non-square pixel aspect")
    if render.use_border:
        log.unsupported_feature("render region (the full frame is rendered)")
    if render.use_motion_blur:
        log.unsupported_feature("motion blur")
    if cam_obj is None:
        log.problem("the scene has no camera: using a default camera at the origin looking down -Z")
        return sphrect.Camera(width=width, height=height, **film_settings(bl_scene))
    cam = cam_obj.data
    to_world = rigid_matrix(cam_obj.matrix_world)
    kind = {"PERSP": "perspective", "ORTHO": "orthographic"}.get(cam.type)
    if kind is None:
        log.unsupported_feature(f"{cam.type.lower()} camera (rendered as perspective)", cam.name)
        kind = "perspective"
    aperture_radius, focus_distance = 0.0, 10.0
    if cam.dof.use_dof:
        focus_distance = cam.dof.focus_distance
        if cam.dof.focus_object is not None:
            # Distance along the view axis, as Cycles measures it.
            target = np.array(cam.dof.focus_object.matrix_world.translation)
            view_dir = -to_world[:3, 2]
            focus_distance = abs(float(np.dot(view_dir, target - to_world[:3, 3])))
        fstop = cam.dof.aperture_fstop
        if fstop > 0:
            # Cycles: aperture radius = focal length / (2 f-stop), focal length in metres;
            # orthographic cameras use 1 / (2 f-stop).
            aperture_radius = (cam.lens * 1e-3 if kind == "perspective" else 1.0) / (2.0 * fstop)
        if cam.dof.aperture_blades >= 3:
            log.unsupported_feature("polygonal aperture (round aperture used)", cam.name)
    return sphrect.Camera(
        width=width, height=height, to_world=to_world.tolist(), type=kind, lens=float(cam.lens),
        sensor_width=float(cam.sensor_width), sensor_height=float(cam.sensor_height), sensor_fit=cam.sensor_fit,
        shift_x=float(cam.shift_x), shift_y=float(cam.shift_y), ortho_scale=float(cam.ortho_scale),
        aperture_radius=float(aperture_radius), focus_distance=float(max(focus_distance, 1e-6)),
        clip_start=float(cam.clip_start), clip_end=float(cam.clip_end), **film_settings(bl_scene))
