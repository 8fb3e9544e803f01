"""Run INSIDE Blender (blender -b file.blend --python this.py -- '<json>'): export the open scene with the
sphrect_blender add-on to a standalone scene file. Arguments (JSON after "--"): addon_dir, out, warnings,
width and height (optional: the render resolution to export, overriding the .blend's)."""
import json
import sys

import bpy

args = json.loads(sys.argv[sys.argv.index("--") + 1])
sys.path.insert(0, args["addon_dir"])
import addon_utils  # noqa: E402

# Registered, not just imported: the light's two-sided switch is the add-on's property.
addon_utils.enable("sphrect_blender", default_set=True)
import sphrect_blender  # noqa: E402

if args.get("width") and args.get("height"):
    bpy.context.scene.render.resolution_x = int(args["width"])
    bpy.context.scene.render.resolution_y = int(args["height"])
    bpy.context.scene.render.resolution_percentage = 100
depsgraph = bpy.context.evaluated_depsgraph_get()
log = sphrect_blender.export_scene(depsgraph, args["out"])
text = log.warning_text() if hasattr(log, "warning_text") else str(log)
with open(args["warnings"], "w") as f:
    json.dump({"warnings": text or "", "blender_version": bpy.app.version_string}, f)
