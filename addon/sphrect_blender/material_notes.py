"""What the Material panel says SPHRECT ignores or approximates in a material: the messages the exporter's own
material export logs for it (io/exporter/materials.py, one source for the panel and the render's warnings).

Exporting a material reads its node tree (0.3-1 ms) and copies the pixels of the images its Image Texture nodes
read (about 180 ms for a 2048 x 2048 image), too slow for every redraw of the panel: the notes are kept per
material until a material, node tree or image changes (a depsgraph update), a file is loaded or an undo step is
taken. What reading an image logs depends on the image's settings, not its pixel values, so an image is read once
per state of its settings (_image_state), and editing a textured material does not copy its images again."""
import bpy
from bpy.app.handlers import persistent

from .io.exporter.log import ExportLog
from .io.exporter.materials import export_material, transparent_surface
from .io.exporter.textures import TextureExport
from .native import load_sphrect

_notes = {}        # material name_full -> (material pointer, [note])
_images_read = {}  # (image name_full, texture_of's other arguments) -> (_image_state, ExportLog of the read)


def _image_state(image):
    """What reading `image` logs depends on (a reload frees its data: has_data False until it is read again)."""
    return (image.source, image.filepath_raw, image.packed_file is not None, tuple(image.size), image.is_float,
            image.colorspace_settings.name, image.alpha_mode, image.has_data)


class _NotesTextures(TextureExport):
    """The exporter's TextureExport for the panel, which never renders: an image read before in the same state is
    not read again (no Texture kept, nothing copied), what its read logged is logged again."""

    def texture_of(self, image, owner, *args, **kwargs):
        if image is None:  # nothing to read; its warning names the material
            return super().texture_of(image, owner, *args, **kwargs)
        key = (image.name_full, args, tuple(sorted(kwargs.items())))
        read = _images_read.get(key)
        if read is None or read[0] != _image_state(image):
            log, self.log = self.log, ExportLog()
            try:
                super().texture_of(image, owner, *args, **kwargs)
            finally:
                image_log, self.log = self.log, log
            read = (_image_state(image), image_log)
            if image.has_data:  # an image that could not be read is tried again (its file may be back)
                _images_read[key] = read
        for what, owners in read[1].unsupported.items():
            for who in owners or [""]:
                self.log.unsupported_feature(what, who)
        for text in read[1].problems:
            self.log.problem(text)
        self.list.append(None)
        return len(self.list) - 1


def material_notes(mat):
    """[note] naming what SPHRECT ignores or approximates in `mat` (a bpy Material), worded as the render's
    warnings word it; [] when it uses everything."""
    key = mat.name_full
    cached = _notes.get(key)
    if cached is None or cached[0] != mat.as_pointer():
        cached = _notes[key] = (mat.as_pointer(), _export_notes(mat))
    return cached[1]


def _export_notes(mat):
    log = ExportLog()
    try:
        sphrect = load_sphrect()
        export_material(sphrect, mat, log, _NotesTextures(sphrect, log))
    except Exception as e:  # the panel must still draw; a render reports the same failure
        return [f"the material could not be exported: {e}"]
    left_out = transparent_surface(mat)  # its triangles are dropped by geometry.triangulate, which warns that
    return ([left_out] if left_out else []) + list(log.unsupported) + log.problems


def forget_notes(images_too=False):
    _notes.clear()
    if images_too:
        _images_read.clear()


@persistent
def _on_depsgraph_update(scene, depsgraph):
    if any(isinstance(u.id, (bpy.types.Material, bpy.types.NodeTree, bpy.types.Image)) for u in depsgraph.updates):
        forget_notes()


@persistent
def _on_load_or_undo(*_):
    forget_notes(images_too=True)


_HANDLERS = ((bpy.app.handlers.depsgraph_update_post, _on_depsgraph_update),
             (bpy.app.handlers.load_post, _on_load_or_undo), (bpy.app.handlers.undo_post, _on_load_or_undo),
             (bpy.app.handlers.redo_post, _on_load_or_undo))


def register():
    for handlers, handler in _HANDLERS:
        if handler not in handlers:
            handlers.append(handler)


def unregister():
    for handlers, handler in _HANDLERS:
        if handler in handlers:
            handlers.remove(handler)
    forget_notes(images_too=True)
