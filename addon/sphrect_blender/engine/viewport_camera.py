"""The 3D view as a sphrect.Camera: the region's view and projection matrices (what Blender draws), so the
rendered image lines up with the viewport in every navigation mode, the camera view included (where the
camera's frame is part of the region, as Cycles renders it)."""
import numpy as np

# The lens the image plane is expressed with (any value works: the sensor width is chosen to match it).
_LENS = 50.0


def camera_from_matrices(sphrect, view_matrix, window_matrix, width, height, aperture_radius=0.0,
                         focus_distance=10.0):
    """sphrect.Camera rendering `width` x `height` pixels of the view given by Blender's region matrices:
    `view_matrix` (world -> view, looking down -Z) and `window_matrix` (OpenGL projection, perspective or
    orthographic, possibly off-centre when the camera view is panned or zoomed)."""
    view = np.array(view_matrix, dtype=np.float64)
    proj = np.array(window_matrix, dtype=np.float64)
    to_world = np.linalg.inv(view)
    for i in range(3):  # a rigid frame (the view matrix may carry a scale)
        to_world[:3, i] /= np.linalg.norm(to_world[:3, i])
    orthographic = abs(proj[3, 3] - 1.0) < 1e-9
    half_width = 1.0 / proj[0, 0]
    if orthographic:
        offset_x, offset_y = -proj[0, 3] / proj[0, 0], -proj[1, 3] / proj[1, 1]
        near = (proj[2, 3] + 1.0) / proj[2, 2]     # the z-range [-far, -near] maps to [-1, 1]
        far = (proj[2, 3] - 1.0) / proj[2, 2]
        clip_start, clip_end = near, far
        if near < 0:  # Blender's orthographic views clip from behind the eye: move the eye back to the near plane
            to_world[:3, 3] += to_world[:3, 2] * -near
            clip_start, clip_end = 0.0, far - near
        kind = "orthographic"
    else:
        offset_x, offset_y = proj[0, 2] / proj[0, 0], proj[1, 2] / proj[1, 1]
        clip_start = proj[2, 3] / (proj[2, 2] - 1.0)
        clip_end = proj[2, 3] / (proj[2, 2] + 1.0)
        kind = "perspective"
    # Horizontal sensor fit: the image plane's half-width fixes the sensor, the height follows the aspect
    # (the region's pixels are square), the shift is in units of the width.
    return sphrect.Camera(
        width=int(width), height=int(height), to_world=to_world.tolist(), type=kind, lens=_LENS,
        sensor_width=float(2.0 * half_width * _LENS), sensor_height=float(2.0 * half_width * _LENS * height / width),
        sensor_fit="HORIZONTAL", shift_x=float(offset_x / (2.0 * half_width)),
        shift_y=float(offset_y / (2.0 * half_width)), ortho_scale=float(2.0 * half_width),
        aperture_radius=float(aperture_radius), focus_distance=float(focus_distance),
        clip_start=float(max(clip_start, 0.0)), clip_end=float(max(clip_end, clip_start + 1e-3)))


def region_camera(sphrect, region, region_3d, scene_camera):
    """sphrect.Camera of a 3D view's region; looking through the scene camera, its depth of field
    (`scene_camera`: the exported sphrect.Camera of the scene, or None)."""
    dof = {}
    if region_3d.view_perspective == "CAMERA" and scene_camera is not None:
        dof = dict(aperture_radius=scene_camera.aperture_radius, focus_distance=scene_camera.focus_distance)
    return camera_from_matrices(sphrect, region_3d.view_matrix, region_3d.window_matrix, region.width,
                                region.height, **dof)


def view_signature(region, region_3d):
    """What the image depends on in the view: the matrices and the region's size (compared between draws)."""
    return (region.width, region.height, region_3d.view_perspective,
            tuple(round(x, 7) for row in region_3d.view_matrix for x in row),
            tuple(round(x, 7) for row in region_3d.window_matrix for x in row))
