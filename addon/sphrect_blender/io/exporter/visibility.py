"""Blender's Object Properties > Visibility > Ray Visibility (obj.visible_<kind>) as the scene's invisible_to: the ray
kinds (sphrect.scene.RAY_KINDS) an object hides from, which the renderer honours as Cycles 3.4 does."""


def invisible_to(obj, kinds, parent=None):
    """The kinds of `kinds` whose obj.visible_<kind> is off, in their order (a tuple; empty: visible to all); for an
    instance, those of its instancing `parent` too (Cycles 3.4's sync_object: the child's flags and the parent's)."""
    return tuple(k for k in kinds if not all(getattr(o, f"visible_{k}", True) for o in (obj, parent) if o is not None))


# The kinds a light's visibility can hide it from besides the camera (its `visible`): Blender shows no Shadow
# toggle for lights (their own shadows are the light's Cast Shadow).
LIGHT_RAY_KINDS = ("diffuse", "glossy", "transmission", "volume_scatter")

# The panel's order of them (Cycles' Ray Visibility panel's): a mesh's, a light's.
PANEL_RAY_KINDS = ("camera", "diffuse", "glossy", "transmission", "volume_scatter", "shadow")
PANEL_LIGHT_RAY_KINDS = ("camera",) + LIGHT_RAY_KINDS


def world_invisible_to(world, kinds):
    """The kinds of `kinds` (sphrect.scene.WORLD_RAY_KINDS) the world's Ray Visibility (world.cycles_visibility, its
    'scatter' the renderer's 'volume_scatter') hides it from."""
    visibility = getattr(world, "cycles_visibility", None)
    if visibility is None:
        return ()
    return tuple(k for k in kinds if not getattr(visibility, "scatter" if k == "volume_scatter" else k, True))


def warn_unhonoured(log, world=None, material=None, exported=None):
    """Warn of the settings Cycles 3.4 honours that SPHRECT does not: an image world's Settings > Surface > Sampling
    None and an emissive material's Multiple Importance off (Cycles then finds that light only with BSDF rays,
    unweighted; SPHRECT samples it as a light: the same image but where a shadow terminator offset lets light samples
    through that BSDF rays never take).  `exported`: the sphrect.World made of `world`, or the sphrect.Material made
    of `material`."""
    if world is not None and getattr(exported, "environment", None) is not None \
            and getattr(getattr(world, "cycles", None), "sampling_method", "AUTOMATIC") == "NONE":
        log.unsupported_feature("world Sampling None (sampled as a light)", world.name)
    if material is not None and exported is not None and any(c > 0 for c in exported.emission) \
            and not getattr(getattr(material, "cycles", None), "sample_as_light", True):
        log.unsupported_feature("emission with Multiple Importance off (sampled as a light)", material.name)
