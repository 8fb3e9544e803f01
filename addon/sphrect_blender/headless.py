"""Headless entry point: what programs outside Blender ask Blender to do with this add-on, by command name
(the study does, python/sphrect/study/cycles.py):

    blender -b --factory-startup scene.blend --python-exit-code 1 --python <add-on>/headless.py -- COMMAND JSON

    export         write the open scene as a sphrect scene file (.sphrect.npz) with the add-on's exporter, from the
                   depsgraph a render evaluates (what F12 and Cycles render: Disable in Renders, render levels).
                   JSON: out; warnings (a JSON file to receive the exporter's warnings and Blender's version);
                   width and height (optional: the resolution to export instead of the .blend's)
    render_cycles  render the open scene with Cycles 3.4 in direct-lighting settings (see cycles_peer.py)

<add-on> is this file's folder wherever the add-on is: the repository's addon/sphrect_blender, an installed
copy, the unpacked zip. Run as a script, this file puts its folder's parent on sys.path and imports the
add-on by its folder's name; the add-on then finds the `sphrect` package as it always does (native.py:
$SPHRECT_PYTHON_PATH first). Scripts already inside Blender may call `run(command, args)` instead.
"""
import importlib
import json
import os
import sys


def export(args):
    import addon_utils
    import bpy
    # Registered, not just imported: the light's two-sided switch is the add-on's property.
    addon_utils.enable(__package__, default_set=True)
    from .io.exporter import export_scene
    if args.get("width") and args.get("height"):
        bpy.context.scene.render.resolution_x = int(args["width"])
        bpy.context.scene.render.resolution_y = int(args["height"])
        bpy.context.scene.render.resolution_percentage = 100
    log = _export_from_render_depsgraph(bpy.context.scene, args["out"], export_scene)
    with open(args["warnings"], "w") as f:
        json.dump({"warnings": log.warning_text(), "blender_version": bpy.app.version_string}, f)


def _export_from_render_depsgraph(scene, out, export_scene):
    """export_scene of the depsgraph a render of `scene` evaluates (its first view layer rendered): Python can make
    only viewport depsgraphs, which keep what Disable in Renders hides and use the modifiers' viewport levels, so a
    render engine of the moment is given it by a render (which draws nothing). Returns the ExportLog."""
    import bpy
    logs = []

    class ExportEngine(bpy.types.RenderEngine):
        bl_idname = "SPHRECT_HEADLESS_EXPORT"
        bl_label = "SPHRECT headless export"

        def render(self, depsgraph):
            if not logs:
                logs.append(export_scene(depsgraph, out))

    bpy.utils.register_class(ExportEngine)
    engine = scene.render.engine
    try:
        scene.render.engine = ExportEngine.bl_idname
        bpy.ops.render.render()
    finally:
        scene.render.engine = engine
        bpy.utils.unregister_class(ExportEngine)
    if not logs:
        raise RuntimeError("the render exported nothing (no view layer is rendered)")
    return logs[0]


def render_cycles(args):
    import bpy
    from .cycles_peer import render_direct_lighting
    render_direct_lighting(bpy.context.scene, args)


COMMANDS = {"export": export, "render_cycles": render_cycles}


def run(command, args):
    if command not in COMMANDS:
        raise ValueError(f"unknown command {command!r}; the commands are {', '.join(COMMANDS)}")
    COMMANDS[command](args)


if __name__ == "__main__":
    _folder = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.dirname(_folder))
    _command, _args = sys.argv[sys.argv.index("--") + 1:]
    importlib.import_module(os.path.basename(_folder) + ".headless").run(_command, json.loads(_args))
