"""Settings: `scene.sphrect` (render settings) and `light.sphrect` (what Blender's lights lack)."""
import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty,
                       StringProperty)

# Blender enum identifier -> sphrect name, in the order shown in the UI.
TECHNIQUES = [
    ("AREA", "area", "Area", "Uniform sampling of the light's area (pdf converted to solid angle)"),
    ("TRIANGLES", "triangles", "Two Triangles", "Solid-angle sampling of the two spherical triangles (Arvo 1995)"),
    ("RECTANGLE", "rectangle", "Spherical Rectangle",
     "Area-preserving solid-angle sampling of the spherical rectangle (Urena et al. 2013)"),
    ("RECTANGLE_COSINE", "rectangle_cosine", "Rectangle + Cosine",
     "Spherical rectangle sampling warped to follow the cosine term"),
]
TECHNIQUE_NAME = {ident: name for ident, name, _, _ in TECHNIQUES}
PATTERNS = [("INDEPENDENT", "Independent", "Independent uniform random numbers"),
            ("STRATIFIED", "Stratified", "Jittered strata"),
            ("LATIN", "Latin Hypercube", "Latin hypercube samples"),
            ("HAMMERSLEY", "Hammersley", "Hammersley point set"),
            ("SOBOL", "Sobol", "Scrambled Sobol sequence")]
MIS = [("NONE", "None", "Light sampling only"),
       ("BALANCE", "Balance", "Balance heuristic between light and BSDF sampling"),
       ("POWER", "Power", "Power heuristic between light and BSDF sampling")]


def _read_reference(path):
    """Read the chosen reference image now, on the main thread (renders in the window run in a job thread)."""
    from .engine import cache_reference_image
    try:
        cache_reference_image(path)
    except (ValueError, RuntimeError) as e:
        print(f"SPHRECT: {e}")


class SPHRECT_SceneSettings(bpy.types.PropertyGroup):
    technique: EnumProperty(name="Technique", items=[(i, l, d) for i, _, l, d in TECHNIQUES],
                            default="RECTANGLE", description="How points on rectangular lights are chosen")
    samples: IntProperty(name="Samples", default=16, min=1, soft_max=4096, description="Camera samples per pixel")
    light_samples: IntProperty(name="Light Samples", default=1, min=1, soft_max=64,
                               description="Light samples per shading point and light")
    pattern: EnumProperty(name="Pattern", items=PATTERNS, default="SOBOL",
                          description="Sample pattern of the light samples")
    mis: EnumProperty(name="MIS", items=MIS, default="BALANCE", description="Multiple importance sampling heuristic")
    seed: IntProperty(name="Seed", default=0, min=0)
    threads: IntProperty(name="Threads", default=0, min=0, description="Render threads (0: all cores)")
    passes: IntProperty(name="Progressive Passes", default=4, min=1, max=256,
                        description="The image is updated at least this many times while rendering the samples")

    compare: BoolProperty(name="Compare Techniques", default=False,
                          description="Render every chosen technique in one go, each as a render pass, "
                                      "and build a side-by-side comparison image")
    compare_area: BoolProperty(name="Area", default=True)
    compare_triangles: BoolProperty(name="Two Triangles", default=True)
    compare_rectangle: BoolProperty(name="Spherical Rectangle", default=True)
    compare_rectangle_cosine: BoolProperty(name="Rectangle + Cosine", default=True)
    equal_time: BoolProperty(name="Equal Time", default=False,
                             description="Give every technique the same time budget instead of the same samples")
    time_budget: FloatProperty(name="Time Budget", default=2.0, min=0.01, subtype="TIME_ABSOLUTE", unit="TIME",
                               description="Seconds per technique in equal-time comparisons")
    reference: EnumProperty(name="Reference", default="RENDER",
                            items=[("NONE", "None", "No reference: no RMSE or error maps"),
                                   ("RENDER", "Render", "A high-sample render with the spherical rectangle technique"),
                                   ("FILE", "EXR File", "An OpenEXR image of the same size")])
    reference_samples: IntProperty(name="Reference Samples", default=256, min=1)
    reference_path: StringProperty(name="Reference EXR", subtype="FILE_PATH", default="",
                                   update=lambda self, context: _read_reference(self.reference_path))

    def compare_techniques(self):
        """sphrect names of the techniques chosen for comparison (all four if none is ticked)."""
        names = [name for ident, name, _, _ in TECHNIQUES if getattr(self, "compare_" + name)]
        return names or [name for _, name, _, _ in TECHNIQUES]

    def renderer_options(self):
        return dict(light_samples=self.light_samples, pattern=self.pattern.lower(), mis=self.mis.lower(),
                    seed=self.seed, threads=self.threads)


class SPHRECT_LightSettings(bpy.types.PropertyGroup):
    two_sided: BoolProperty(name="Two-Sided", default=False,
                            description="Area light emits from both faces (Blender's area lights emit along -Z only)")


classes = (SPHRECT_SceneSettings, SPHRECT_LightSettings)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.sphrect = PointerProperty(type=SPHRECT_SceneSettings)
    bpy.types.Light.sphrect = PointerProperty(type=SPHRECT_LightSettings)


def unregister():
    del bpy.types.Light.sphrect
    del bpy.types.Scene.sphrect
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
