"""The sphrect names the add-on offers (techniques, sample patterns, MIS modes, light selections, ellipse techniques)
as Blender enum items.

One source: the native module's lists (`sphrect.techniques`, `sphrect.patterns`, `sphrect.mis_modes`,
`sphrect.light_selections`, `sphrect.ellipse_techniques`, `sphrect.pixel_filters`). An
item's identifier is the name upper-cased ('rectangle_cosine' -> 'RECTANGLE_COSINE': what scripts, tests and
the scene builders set) and its number is the name's position in the module's list, which is what a .blend
file stores: the module's lists may grow at the end only. The add-on's own part is the UI text (the *_LABELS
tables, keyed by name). Without a loadable module (not built, another Python) the add-on still registers,
so that a render can say what is missing; the names then come from the labels' keys, which the Blender
tests keep equal to the module's lists.
"""
from .native import load_sphrect

ENGINE_ID = "SPHRECT"  # the render engine's bl_idname (scene.render.engine), for which the panels show

# sphrect name -> (label, description) shown in Blender's UI.
TECHNIQUE_LABELS = {
    "area": ("Area (uniform)",
             "Rectangle lights: points spread evenly over the light's surface. Simple and cheap, but noisy for lights "
             "close to or large from the shaded point. Disk lights follow the Disk Lights setting"),
    "triangles": ("Solid angle (two triangles)",
                  "Rectangle lights: points spread evenly over the light as seen from the shaded point, by splitting "
                  "it into two spherical triangles (Arvo 1995). A baseline for the spherical rectangle"),
    "rectangle": ("Solid angle (spherical rectangle)",
                  "Rectangle lights: points spread evenly over the light as seen from the shaded point, with the "
                  "area-preserving map of Urena et al. 2013, which keeps the sample pattern's stratification. "
                  "Emissive mesh rectangles too"),
    "rectangle_cosine": ("Solid angle + cosine",
                         "Rectangle lights: the spherical rectangle warped to follow the cosine at the shaded point, "
                         "so more points land where the light shines more directly"),
    "rectangle_projected": ("Projected solid angle (exact cosine)",
                            "Rectangle lights: points spread in proportion to the cosine at the shaded point, exactly "
                            "(Peters 2021), over the part of the light above its horizon: on a diffuse surface an "
                            "unshadowed light is noise-free"),
    "rectangle_ltc": ("Projected + glossy lobe (LTC)",
                      "Rectangle lights: on glossy surfaces, points also spread in proportion to the GGX highlight "
                      "(its linearly transformed cosine, Heitz et al. 2016; Peters 2021), mixed with the projected "
                      "solid angle for the rest of the surface's reflection"),
}
PATTERN_LABELS = {
    "independent": ("Independent", "Independent uniform random numbers"),
    "stratified": ("Stratified", "Jittered strata"),
    "latin": ("Latin Hypercube", "Latin hypercube samples"),
    "hammersley": ("Hammersley", "Hammersley point set"),
    "sobol": ("Sobol", "Scrambled Sobol sequence"),
}
MIS_LABELS = {
    "none": ("None", "Light sampling only"),
    "balance": ("Balance", "Balance heuristic between light and BSDF sampling"),
    "power": ("Power", "Power heuristic between light and BSDF sampling"),
}

LIGHT_SELECTION_LABELS = {
    "power": ("Power", "Area lights by power; point and spot lights each on every sample"),
    "tree": ("Light Tree", "Every area, point and spot light through a light tree (power, distance, orientation)"),
    "ris": ("Light Tree + RIS", "Several light-tree candidates per light sample, one kept by its unshadowed "
                                "contribution (resampled importance sampling)"),
}

ELLIPSE_TECHNIQUE_LABELS = {
    "area": ("Area (uniform)", "Disk and ellipse lights: points spread evenly over the light's surface"),
    "spherical_ellipse": ("Solid angle (spherical ellipse)",
                          "Disk and ellipse lights: points spread evenly over the light as seen from the shaded point "
                          "(Guillen et al. 2017) where that pays, i.e. close to the light; by area where the light is "
                          "small or distant enough that both give the same"),
}

# Cycles' Film > Pixel Filter (render/pixel_filter.h): where in and around its pixel a camera sample looks.
PIXEL_FILTER_LABELS = {
    "box": ("Box", "Every sample counts alike over the pixel's own square: the sharpest edges, the most aliasing "
                   "(Cycles renders every box 1 pixel wide, and so does SPHRECT from Blender). With Exact Light "
                   "Edges the least noise where the edges of visible lights cross pixels (computed exactly; for the "
                   "other filters estimated)"),
    "gaussian": ("Gaussian", "Samples spread around the pixel centre as a Gaussian of standard deviation Width / 4 "
                             "(cut at 1.5 Widths): smooth edges, some blur"),
    "blackman_harris": ("Blackman-Harris", "Samples spread around the pixel centre as a Blackman-Harris window "
                                           "Width to either side: smooth edges with less blur than a Gaussian "
                                           "(Cycles' default, at 1.5 pixels)"),
}
DEFAULT_PIXEL_FILTER, DEFAULT_FILTER_WIDTH = "blackman_harris", 1.5  # Cycles' defaults


def identifier(name):
    """Blender enum identifier of a sphrect name."""
    return name.upper()


def sphrect_name(enum_identifier):
    """sphrect name of a Blender enum identifier (the inverse of `identifier`)."""
    return enum_identifier.lower()


def label(name, labels):
    """(label, description) of a name; a name the add-on has no text for yet reads 'Rectangle Cosine'."""
    return labels.get(name, (name.replace("_", " ").title(), ""))


def enum_items(names, labels):
    """EnumProperty items (identifier, label, description, number) in the module's order."""
    return [(identifier(n), *label(n, labels), number) for number, n in enumerate(names)]


def _module_names(attribute, labels):
    try:
        return tuple(getattr(load_sphrect(), attribute))
    except (ImportError, AttributeError):
        return tuple(labels)


TECHNIQUES = _module_names("techniques", TECHNIQUE_LABELS)
PATTERNS = _module_names("patterns", PATTERN_LABELS)
MIS_MODES = _module_names("mis_modes", MIS_LABELS)
LIGHT_SELECTIONS = _module_names("light_selections", LIGHT_SELECTION_LABELS)
ELLIPSE_TECHNIQUES = _module_names("ellipse_techniques", ELLIPSE_TECHNIQUE_LABELS)
PIXEL_FILTERS = _module_names("pixel_filters", PIXEL_FILTER_LABELS)


def _module_value(attribute, fallback):
    try:
        return getattr(load_sphrect(), attribute)
    except (ImportError, AttributeError):
        return fallback


# The render settings' defaults: the module's (sphrect.RENDER_DEFAULTS, from render/options.h).  Without a module
# the add-on only registers to say what is missing, so any valid value serves: each list's first, False, 0.
RENDER_DEFAULTS = _module_value("RENDER_DEFAULTS", {
    "techniques": TECHNIQUES[:1], "light_samples": 1, "pattern": PATTERNS[0], "mis": MIS_MODES[0], "seed": 0,
    "threads": 0, "light_selection": LIGHT_SELECTIONS[0], "ellipse_technique": ELLIPSE_TECHNIQUES[0],
    "analytic_light_coverage": False, "bsdf_samples_on_diffuse": False, "ris_candidates": 1})

# Light selection "ris": the most candidates per light sample (the module's limit).
MAX_RIS_CANDIDATES = int(_module_value("MAX_RIS_CANDIDATES", 1))


# The Filter Width's range, pixels (the module's float32 limits, rounded for the UI; without the module, Blender's).
FILTER_WIDTH_RANGE = tuple(round(float(_module_value(name, fallback)), 6)
                           for name, fallback in (("MIN_PIXEL_FILTER_WIDTH", 0.01), ("MAX_PIXEL_FILTER_WIDTH", 10.0)))
