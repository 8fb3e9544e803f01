"""Settings: `scene.sphrect` (render settings) and `light.sphrect` (what Blender's lights lack)."""
import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty,
                       StringProperty)

from .images import cache_reference_image
from .names import (DEFAULT_FILTER_WIDTH, DEFAULT_PIXEL_FILTER, ELLIPSE_TECHNIQUE_LABELS, ELLIPSE_TECHNIQUES,
                    FILTER_WIDTH_RANGE, LIGHT_SELECTION_LABELS, LIGHT_SELECTIONS, MAX_RIS_CANDIDATES, MIS_LABELS,
                    MIS_MODES, PATTERN_LABELS, PATTERNS, PIXEL_FILTER_LABELS, PIXEL_FILTERS, RENDER_DEFAULTS,
                    TECHNIQUE_LABELS, TECHNIQUES, enum_items, identifier, label, sphrect_name)


def _read_reference(path):
    """Read the chosen reference image now, on the main thread (renders in the window run in a job thread)."""
    try:
        cache_reference_image(path)
    except (ValueError, RuntimeError) as e:
        print(f"SPHRECT: {e}")


class SPHRECT_SceneSettings(bpy.types.PropertyGroup):
    technique: EnumProperty(name="Technique", items=enum_items(TECHNIQUES, TECHNIQUE_LABELS),
                            default=identifier(RENDER_DEFAULTS["techniques"][0]),
                            description="How points on rectangular lights are chosen")
    samples: IntProperty(name="Samples", default=16, min=1, soft_max=4096, description="Camera samples per pixel")
    time_limit: FloatProperty(name="Time Limit", default=0.0, min=0.0, subtype="TIME_ABSOLUTE", unit="TIME",
                              description="Stop an F12 render after this many seconds even if its samples are not "
                                          "done, keeping the samples rendered (0: no limit; checked between the "
                                          "renderer's calls, at most 262,144 camera samples each)")
    light_samples: IntProperty(name="Light Samples", default=RENDER_DEFAULTS["light_samples"], min=1, soft_max=64,
                               description="Light samples per camera sample, each choosing one light and paired "
                                           "with a BSDF sample")
    pattern: EnumProperty(name="Pattern", items=enum_items(PATTERNS, PATTERN_LABELS),
                          default=identifier(RENDER_DEFAULTS["pattern"]),
                          description="Sample pattern of the light samples")
    mis: EnumProperty(name="MIS", items=enum_items(MIS_MODES, MIS_LABELS), default=identifier(RENDER_DEFAULTS["mis"]),
                      description="Multiple importance sampling heuristic")
    light_selection: EnumProperty(name="Light Selection", items=enum_items(LIGHT_SELECTIONS, LIGHT_SELECTION_LABELS),
                                  default=identifier(RENDER_DEFAULTS["light_selection"]),
                                  description="How each light sample chooses its light")
    ris_candidates: IntProperty(name="RIS Candidates", default=RENDER_DEFAULTS["ris_candidates"], min=1,
                                max=MAX_RIS_CANDIDATES, soft_max=min(32, MAX_RIS_CANDIDATES),
                                description="Light Tree + RIS: the light tree's candidates per light sample, each "
                                            "weighed by what it would add unshadowed, one kept for the shadow ray "
                                            "(more: less noise among many lights, but each costs a tree descent and "
                                            "a BSDF evaluation)")
    ellipse_technique: EnumProperty(name="Disk Lights", items=enum_items(ELLIPSE_TECHNIQUES, ELLIPSE_TECHNIQUE_LABELS),
                                    default=identifier(RENDER_DEFAULTS["ellipse_technique"]),
                                    description="How points on disk and ellipse lights are chosen")
    analytic_light_coverage: BoolProperty(
        name="Exact Light Edges", default=RENDER_DEFAULTS["analytic_light_coverage"],
        description="For rectangle and disk lights seen by the camera, compute exactly how much of each pixel they "
                    "cover instead of estimating it from the samples (unbiased; removes the noise of their edges "
                    "where nothing hides them; with Gaussian and Blackman-Harris filters the filter's share is "
                    "estimated from cheap inside-tests, nearly as good; not in a volume or with depth of field)")
    bsdf_samples_on_diffuse: BoolProperty(
        name="MIS on Diffuse", default=RENDER_DEFAULTS["bsdf_samples_on_diffuse"],
        description="Also draw BSDF samples (MIS) at purely diffuse surfaces. Off, they take light samples alone "
                    "where the lights are sampled by solid angle: the same image on average, faster, and less "
                    "noisy in most scenes; glossy surfaces, area sampling and scenes with emissive meshes keep "
                    "MIS either way")
    seed: IntProperty(name="Seed", default=RENDER_DEFAULTS["seed"], min=0)
    pixel_filter: EnumProperty(name="Pixel Filter", items=enum_items(PIXEL_FILTERS, PIXEL_FILTER_LABELS),
                               default=identifier(DEFAULT_PIXEL_FILTER),
                               description="How a pixel weighs what its camera samples see, as Cycles' Film > Pixel "
                                           "Filter (the Cycles comparisons use the same)")
    filter_width: FloatProperty(name="Width", default=DEFAULT_FILTER_WIDTH, min=FILTER_WIDTH_RANGE[0],
                                max=FILTER_WIDTH_RANGE[1], subtype="PIXEL",
                                description="Width of the pixel filter: lower is crisper, higher softer with less "
                                            "aliasing (Box is always 1 pixel, as in Cycles)")
    threads: IntProperty(name="Threads", default=RENDER_DEFAULTS["threads"], min=0,
                         description="Render threads (0: all cores)")
    passes: IntProperty(name="Progressive Passes", default=4, min=1, max=256,
                        description="The image is updated at least this many times while rendering the samples")

    viewport_samples: IntProperty(name="Viewport Samples", default=64, min=1, soft_max=4096,
                                  description="Camera samples per pixel of the 3D view's Rendered shading")
    viewport_compare: BoolProperty(name="Viewport Compare", default=False,
                                   description="Rendered shading shows two techniques side by side: the Technique "
                                               "on the left, the Compare With technique on the right")
    viewport_compare_technique: EnumProperty(name="Compare With", items=enum_items(TECHNIQUES, TECHNIQUE_LABELS),
                                             default="AREA",
                                             description="The technique of the right half of the viewport compare")

    compare: BoolProperty(name="Compare Techniques", default=False,
                          description="Render every chosen technique in one go, each as a render pass, "
                                      "and build a side-by-side comparison image")
    # compare_<technique>: BoolProperty per technique, compare_light_selection_<name> per light selection and
    # compare_ellipse_technique_<name> per ellipse technique, added below from the module's lists.
    equal_time: BoolProperty(name="Equal Time", default=False,
                             description="Give every technique the same time budget instead of the same samples")
    time_budget: FloatProperty(name="Time Budget", default=2.0, min=0.01, subtype="TIME_ABSOLUTE", unit="TIME",
                               description="Seconds per technique in equal-time comparisons (whole passes of "
                                           "one sample: a budget shorter than one pass is overrun by that pass)")
    reference: EnumProperty(name="Reference", default="RENDER",
                            items=[("NONE", "None", "No reference: no RMSE or error maps"),
                                   ("RENDER", "Render", "A high-sample render with the spherical rectangle technique"),
                                   ("FILE", "EXR File", "An OpenEXR image of the same size")])
    reference_samples: IntProperty(name="Reference Samples", default=256, min=1)
    reference_path: StringProperty(name="Reference EXR", subtype="FILE_PATH", default="",
                                   update=lambda self, context: _read_reference(self.reference_path))

    def compare_techniques(self):
        """sphrect names of the techniques chosen for comparison (all of them if none is ticked)."""
        names = [name for name in TECHNIQUES if getattr(self, compare_switch(name))]
        return names or list(TECHNIQUES)

    def compare_light_selections(self):
        """sphrect names of the light selections chosen for comparison: the ticked ones, else (as before the
        switches existed) the scene's light_selection."""
        names = [name for name in LIGHT_SELECTIONS if getattr(self, compare_light_selection_switch(name))]
        return names or [sphrect_name(self.light_selection)]

    def compare_ellipse_techniques(self):
        """sphrect names of the ellipse techniques chosen for comparison: the ticked ones, else the scene's
        ellipse_technique."""
        names = [name for name in ELLIPSE_TECHNIQUES if getattr(self, compare_ellipse_technique_switch(name))]
        return names or [sphrect_name(self.ellipse_technique)]

    def renderer_options(self):
        return dict(light_samples=self.light_samples, pattern=sphrect_name(self.pattern),
                    mis=sphrect_name(self.mis), light_selection=sphrect_name(self.light_selection),
                    ris_candidates=self.ris_candidates,
                    ellipse_technique=sphrect_name(self.ellipse_technique),
                    analytic_light_coverage=self.analytic_light_coverage,
                    bsdf_samples_on_diffuse=self.bsdf_samples_on_diffuse, seed=self.seed, threads=self.threads)


def compare_switch(technique):
    """The scene setting that picks `technique` for comparison."""
    return "compare_" + technique


def compare_light_selection_switch(light_selection):
    """The scene setting that picks `light_selection` for comparison."""
    return "compare_light_selection_" + light_selection


def compare_ellipse_technique_switch(ellipse_technique):
    """The scene setting that picks `ellipse_technique` for comparison."""
    return "compare_ellipse_technique_" + ellipse_technique


SPHRECT_SceneSettings.__annotations__.update(
    {compare_switch(t): BoolProperty(name=label(t, TECHNIQUE_LABELS)[0], default=True) for t in TECHNIQUES})
SPHRECT_SceneSettings.__annotations__.update(
    {compare_light_selection_switch(n): BoolProperty(
        name=label(n, LIGHT_SELECTION_LABELS)[0], default=False,
        description="Render the compared techniques with this light selection too, each as its own pass (none "
                    "ticked: the Sampling panel's Light Selection)") for n in LIGHT_SELECTIONS})
SPHRECT_SceneSettings.__annotations__.update(
    {compare_ellipse_technique_switch(n): BoolProperty(
        name=label(n, ELLIPSE_TECHNIQUE_LABELS)[0], default=False,
        description="Render the compared techniques with disk and ellipse lights sampled this way too, each as its "
                    "own pass (none ticked: the Sampling panel's Disk Lights)") for n in ELLIPSE_TECHNIQUES})


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
