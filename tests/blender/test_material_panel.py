"""The Material properties' SPHRECT panel: for the active material, what the exporter ignores or approximates,
in the render warnings' words (the exporter's own material export, cached until a material, node tree or image
changes)."""
from types import SimpleNamespace

import bpy
import numpy as np

from conftest import addon_module, builders, export, lit_test_scene


def notes_module():
    return addon_module("material_notes")


def on_box(scene, mat):
    """Puts `mat` on the lit test scene's box (so that its edits reach the depsgraph, as in the UI)."""
    lit_test_scene(scene)
    bpy.data.objects["Box"].data.materials[0] = mat
    bpy.context.view_layer.update()
    return mat


class _Layout:
    """What a panel's draw() calls on its layout, recording the labels."""

    def __init__(self):
        self.labels = []

    def column(self, **_):
        return self

    def label(self, text="", icon="NONE"):
        self.labels.append((text, icon))


def drawn_labels(mat, width=300):
    panel = bpy.types.MATERIAL_PT_sphrect_material
    context = SimpleNamespace(engine="SPHRECT", material=mat, region=SimpleNamespace(width=width),
                              preferences=bpy.context.preferences)
    assert panel.poll(context)
    layout = _Layout()
    panel.draw(SimpleNamespace(layout=layout), context)
    return layout.labels


def test_panel_lists_what_the_export_ignores(empty_scene):
    rough, glossy = builders.node_material("Rough Glossy", "ShaderNodeBsdfGlossy")
    glossy.distribution = "ASHIKHMIN_SHIRLEY"
    on_box(empty_scene, rough)
    notes = notes_module().material_notes(rough)
    assert notes == ["Glossy BSDF distribution 'Ashikhmin-Shirley' (GGX used)"]
    labels = drawn_labels(rough, width=600)
    assert labels[0] == ("Ignored or approximated by SPHRECT:", "NONE")
    assert " ".join(text for text, _ in labels[1:]) == notes[0]  # wrapped to the panel's width, nothing lost
    assert [icon for _, icon in labels[1:]] == ["DOT"] + ["BLANK1"] * (len(labels) - 2)
    narrow = drawn_labels(rough, width=200)
    assert len(narrow) > len(labels) and " ".join(text for text, _ in narrow) == " ".join(t for t, _ in labels)
    # One source: the render's warnings name the same thing for that material.
    _, log = export()
    assert log.unsupported[notes[0]] == ["Rough Glossy"]

    plain = builders.material("Plain", kind="principled")
    assert notes_module().material_notes(plain) == []
    assert drawn_labels(plain) == [("Nothing ignored by SPHRECT", "CHECKMARK")]
    assert not bpy.types.MATERIAL_PT_sphrect_material.poll(
        SimpleNamespace(engine="CYCLES", material=plain))


def test_left_out_surfaces_and_problems_are_listed(empty_scene):
    volume_only = bpy.data.materials.new("Fog")
    volume_only.use_nodes = True
    tree = volume_only.node_tree
    tree.nodes.remove(tree.nodes["Principled BSDF"])
    scatter = tree.nodes.new("ShaderNodeVolumeScatter")
    tree.links.new(scatter.outputs[0], tree.nodes["Material Output"].inputs["Volume"])
    assert notes_module().material_notes(volume_only) == []  # an object volume: left out of the meshes, unwarned
    no_image, bsdf = builders.node_material("No Image", "ShaderNodeBsdfPrincipled")
    builders.image_texture(no_image, None, bsdf.inputs["Base Color"])
    assert notes_module().material_notes(no_image) == [
        "an Image Texture node of material 'No Image' has no image: magenta, as Cycles shows it"]


def test_notes_cached_until_the_material_changes(empty_scene):
    """draw() is called at every redraw: the export runs once per change of the material (a depsgraph update),
    not per draw."""
    rough, bsdf = builders.node_material("Rough Glossy", "ShaderNodeBsdfGlossy")
    bsdf.distribution = "ASHIKHMIN_SHIRLEY"
    on_box(empty_scene, rough)
    first = notes_module().material_notes(rough)
    assert first and notes_module().material_notes(rough) is first  # not exported again
    bsdf.distribution = "GGX"
    bpy.context.view_layer.update()  # the depsgraph update the UI's edit makes
    assert notes_module().material_notes(rough) == []


def test_an_image_is_read_once_across_edits_of_its_material(empty_scene):
    """Re-exporting a textured material after an edit does not copy its image's pixels again (the copy is what
    costs: about 180 ms for a 2048 x 2048 image) while the image's settings stay the same; what reading it logged
    is listed each time. An image that could not be read is tried again at each export."""
    notes = notes_module()
    mat, bsdf = builders.node_material("Textured", "ShaderNodeBsdfPrincipled")
    image = builders.packed_image("Pattern", np.random.default_rng(1).uniform(0, 1, (8, 8, 3)))
    image.colorspace_settings.name = "Filmic Log"  # a colour space the exporter approximates (warned)
    builders.image_texture(mat, image, bsdf.inputs["Base Color"])
    on_box(empty_scene, mat)
    colorspace_note = "image colour space 'Filmic Log' (read as linear)"
    assert notes.material_notes(mat) == [colorspace_note]
    read = dict(notes._images_read)
    assert [key[0] for key in read] == ["Pattern"]
    bsdf.inputs["Metallic"].default_value = 0.5
    bpy.context.view_layer.update()
    assert notes.material_notes(mat) == [colorspace_note]  # exported again, the image's note logged again ...
    assert all(notes._images_read[key] is value for key, value in read.items())  # ... from the read before
    image.colorspace_settings.name = "sRGB"
    bpy.context.view_layer.update()
    assert notes.material_notes(mat) == []  # read again: its settings changed

    missing = bpy.data.images.new("texscn.png", 4, 4)
    missing.source, missing.filepath = "FILE", "/nonexistent/texscn.png"
    mat.node_tree.nodes["Image Texture"].image = missing
    bpy.context.view_layer.update()
    expected = ["image 'texscn.png' could not be read (/nonexistent/texscn.png): magenta, as Cycles shows it"]
    assert notes.material_notes(mat) == expected
    assert not any(key[0] == "texscn.png" for key in notes._images_read)
