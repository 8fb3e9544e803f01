"""What the Sampling panel says about the scene's lights that the chosen Technique does not sample: the
Technique is for rectangle lights (and emissive mesh rectangles); disks and ellipses follow Disk Lights; point,
spot and sun lights have no area to sample (with a radius or an angle, the cone they subtend is sampled)."""
from .names import ELLIPSE_TECHNIQUE_LABELS, TECHNIQUE_LABELS, label, sphrect_name

RECTANGLE_SHAPES = {"SQUARE", "RECTANGLE"}
DISK_SHAPES = {"DISK", "ELLIPSE"}


def count_lights(scene):
    """(rectangles, disks, delta lights) among the scene's light objects."""
    rectangles = disks = delta = 0
    for obj in scene.objects:
        if obj.type != "LIGHT":
            continue
        light = obj.data
        if light.type == "AREA":
            rectangles += light.shape in RECTANGLE_SHAPES
            disks += light.shape in DISK_SHAPES
        else:
            delta += 1
    return rectangles, disks, delta


def light_shape_notes(scene, settings):
    """Lines for the Sampling panel, empty when the Technique samples every light of the scene."""
    rectangles, disks, delta = count_lights(scene)
    technique = label(sphrect_name(settings.technique), TECHNIQUE_LABELS)[0]
    notes = []
    if not rectangles and (disks or delta):
        notes.append(f"No rectangle lights: {technique} changes only emissive mesh rectangles")
    if disks:
        ellipse = label(sphrect_name(settings.ellipse_technique), ELLIPSE_TECHNIQUE_LABELS)[0]
        notes.append(f"{disks} disk/ellipse light{'s' * (disks > 1)}: by Disk Lights ({ellipse})")
    if delta:
        notes.append(f"{delta} point/spot/sun light{'s' * (delta > 1)}: no area to sample (soft: by cone)")
    return notes
