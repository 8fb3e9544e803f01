"""sphrect: solid-angle sampling of rectangular lights (Urena, Fajardo & King, EGSR 2013)
and a small Embree direct-lighting renderer built on it."""
from ._native import *  # noqa: F401,F403  (sampling core and renderer, C++)
from .scene import (Camera, EllipseLight, Environment, Material, MaterialLayer, Medium, Mesh, MixFactor,  # noqa: F401
                    NodeInstruction, NodeProgram,
                    PointLight, RectLight, Scene, SpotLight, SunLight, Texture, TextureLookup, Volume, World,
                    load_scene, save_scene)
from .render import RENDER_DEFAULTS, Renderer, dropped_samples_message, mix_lobe_slots, render  # noqa: E402,F401
from .build import build_hash  # noqa: E402,F401
from .distributed import render_distributed  # noqa: E402,F401  (Dask itself is the client's: not imported here)
