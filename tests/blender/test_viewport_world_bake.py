"""The Rendered viewport does not wait for a world's bake (io/exporter/world_bake.py: in_background, BackgroundBakes):
its export of a world not yet baked returns with a stand-in and the bake running in a child Blender; when the child
ends, the world is exported again with the bake; a newer edit supersedes a running bake; a failed one keeps the
stand-in; no child outlives the viewport or Blender.  Small gradient worlds (32 x 16) baked into a cache folder of the
test's own; every wait on a child is bounded (WAIT_SECONDS), none is a fixed sleep."""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import bpy
import numpy as np
import pytest

from conftest import addon_module, builders

WAIT_SECONDS = 120.0  # a bound on a child bake, never reached when it works (it takes ~2-4 s)


def world_bake():
    return addon_module("io.exporter.world_bake")


@pytest.fixture
def sky_scene(empty_scene, tmp_path, monkeypatch):
    """A lit ground under a Gradient world of Strength 2 over a Background of its own Color (0.1, 0.2, 0.3), baked
    at 32 x 16 into tmp_path; (scene, world, session), the session freed afterwards."""
    bake = world_bake()
    monkeypatch.setattr(bake, "CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(bake, "BAKE_WIDTH", 32)
    monkeypatch.setattr(bake, "BAKE_HEIGHT", 16)
    bake._memory.clear()
    builders.mesh_object("Ground", "plane", builders.material("Ground"), size=8)
    builders.area_light("Light", power=50.0, location=(0, 0, 2))
    world = bpy.data.worlds.new("Gradient")
    world.use_nodes = True
    tree = world.node_tree
    background = tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.1, 0.2, 0.3, 1.0)
    background.inputs["Strength"].default_value = 2.0
    gradient = tree.nodes.new("ShaderNodeTexGradient")
    tree.links.new(gradient.outputs["Color"], background.inputs["Color"])
    empty_scene.world = world
    bpy.context.view_layer.update()
    session = addon_module("engine.viewport").ViewportSession()
    yield empty_scene, world, session
    session.free()


def depsgraph():
    return bpy.context.evaluated_depsgraph_get()


def edited(session, change):
    """Apply `change` to the data; the session sees the depsgraph's updates as view_update would."""
    def handler(_scene, graph):
        session.update(graph)

    bpy.app.handlers.depsgraph_update_post.append(handler)
    try:
        change()
        depsgraph().update()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(handler)


def land(session):
    """Wait for the session's running bake to end, then do what the timer and the next draw do."""
    assert session.bakes.job.join(WAIT_SECONDS), "the bake did not end"
    assert session.poll_bake() and session.world_stale
    session.refresh_world(depsgraph())
    assert not session.world_stale and not session.bakes.pending


def environment_pixels(scene):
    environment = scene.world.environment
    assert environment is not None
    return scene.textures[environment.texture].pixels


def no_render(*_):
    pytest.fail("a bake was rendered again")


@pytest.mark.slow
def test_uncached_world_is_baked_in_the_background(sky_scene, tmp_path, monkeypatch):
    """The first export returns with a constant stand-in (the Background's own Color x Strength) and the bake
    running; once the child ends the world is exported with its bake, which a render then reads from the cache."""
    scene, world, session = sky_scene
    session.update(depsgraph())
    assert session.bakes.pending and session.world_stale is False
    assert session.scene.world.environment is None and session.scene.textures == []
    assert session.scene.world.background == pytest.approx((0.2, 0.4, 0.6))
    assert session._bake_state() == " | Baking world…"
    assert not session.poll_bake() or session.world_stale  # (the child may not have ended yet)
    land(session)
    baked = environment_pixels(session.scene)
    assert baked.shape == (16, 32, 3) and baked.max() > 0
    assert session.scene.world.background == pytest.approx(tuple(world_bake().sphere_mean(baked)))
    assert session._bake_state() == "" and not session.poll_bake()
    assert len(list(tmp_path.glob("*.npy"))) == 1
    world_bake()._memory.clear()
    monkeypatch.setattr(world_bake(), "_render_world", no_render)
    assert np.array_equal(world_bake().bake_world(world), baked)  # F12's export: from the cache folder


@pytest.mark.slow
def test_a_newer_edit_supersedes_the_running_bake(sky_scene, tmp_path):
    """An edit while no bake runs shows the world's previous bake until the new one lands; an edit while a bake
    runs kills that child, whose result is neither shown nor cached; the last edit's bake is shown."""
    scene, world, session = sky_scene
    strength = world.node_tree.nodes["Background"].inputs["Strength"]
    session.update(depsgraph())
    land(session)
    first = environment_pixels(session.scene).copy()

    edited(session, lambda: setattr(strength, "default_value", 4.0))
    superseded = session.bakes.job
    assert superseded is not None
    assert np.array_equal(environment_pixels(session.scene), first)  # the stand-in: the world's previous bake
    edited(session, lambda: setattr(strength, "default_value", 8.0))
    assert superseded.done() and session.bakes.job is not superseded
    with pytest.raises(world_bake().BakeError, match="cancelled"):
        superseded.wait(0)
    assert superseded.signature != session.bakes.job.signature
    land(session)
    last = environment_pixels(session.scene)
    assert np.allclose(last, 4 * first, rtol=0.01, atol=1e-3)  # Strength 8 against 2
    assert not (tmp_path / f"{superseded.signature}.npy").exists()
    assert superseded.signature not in world_bake()._memory
    assert len(list(tmp_path.glob("*.npy"))) == 2


def test_a_failed_background_bake_keeps_the_stand_in(sky_scene, monkeypatch, capsys):
    """A child that fails: the stand-in stays, the failure is printed as the export's scene problem (as a render's
    is reported) and named in the view's status, and the same world is not baked again until it changes."""
    scene, world, session = sky_scene
    monkeypatch.setattr(world_bake(), "_child_command", lambda job: ["/bin/sh", "-c", "echo no sky here; exit 3"])
    session.update(depsgraph())
    assert session.bakes.pending
    land(session)
    assert session.scene.world.environment is None
    assert session.scene.world.background == pytest.approx((0.2, 0.4, 0.6))
    printed = capsys.readouterr().out
    assert "could not be baked" in printed and "exit code 3" in printed and "no sky here" in printed
    assert "failed" in session._bake_state()
    session.refresh_world(depsgraph())
    assert not session.bakes.pending  # not tried again
    edited(session, lambda: setattr(world.node_tree.nodes["Background"].inputs["Strength"], "default_value", 3.0))
    assert session.bakes.pending and session._bake_state() == " | Baking world…"  # a changed world: baked again


def test_leaving_the_viewport_kills_its_bake(sky_scene, tmp_path):
    """Freeing the session (the view leaves Rendered shading) kills the child at once and drops its result."""
    scene, world, session = sky_scene
    session.update(depsgraph())
    job = session.bakes.job
    session.free()
    # A child Blender starts in about a second: freed a few ms after its start, it was still running.
    assert job.process.returncode == -signal.SIGKILL
    assert not session.bakes.pending and not os.path.exists(job._folder)
    assert list(tmp_path.glob("*.npy")) == []


def test_a_world_that_needs_no_bake_any_more_ends_the_running_one(sky_scene):
    """The world edited into a constant while its bake runs: the child is killed, the constant shown, the status
    clear."""
    scene, world, session = sky_scene
    session.update(depsgraph())
    job = session.bakes.job
    tree = world.node_tree
    edited(session, lambda: tree.links.remove(tree.nodes["Background"].inputs["Color"].links[0]))
    assert job.done() and not session.bakes.pending and session._bake_state() == ""
    assert session.scene.world.environment is None
    assert session.scene.world.background == pytest.approx((0.2, 0.4, 0.6))


@pytest.mark.slow
def test_a_render_waits_for_the_viewport_bake_of_the_same_world(sky_scene, monkeypatch):
    """A render (outside in_background) of a world the viewport is baking waits for that child instead of starting
    its own; the viewport then lands the same pixels."""
    scene, world, session = sky_scene
    session.update(depsgraph())
    assert session.bakes.pending
    monkeypatch.setattr(world_bake(), "_render_world", no_render)
    rendered = world_bake().bake_world(world)
    land(session)
    assert np.array_equal(environment_pixels(session.scene), rendered)


QUIT_SCRIPT = """
import os, signal, sys, time
sys.path[:0] = sys.argv[-4:-2]  # the add-on's folder and the sphrect package's
import addon_utils, bpy
addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
bake = sys.modules["sphrect_blender.io.exporter.world_bake"]
bake.CACHE_DIR = sys.argv[-2]
bake.BAKE_WIDTH, bake.BAKE_HEIGHT = 2048, 1024  # a bake of a minute or more: still running when this Blender ends
bake.PEAK_SAMPLES = 1 << 16
world = bpy.data.worlds.new("Sky")
world.use_nodes = True
world.node_tree.links.new(world.node_tree.nodes.new("ShaderNodeTexSky").outputs[0],
                          world.node_tree.nodes["Background"].inputs["Color"])
bpy.context.scene.world = world
session = sys.modules["sphrect_blender.engine.viewport"].ViewportSession()
session.update(bpy.context.evaluated_depsgraph_get())
job = session.bakes.job
output, end = os.path.join(job._folder, "output.txt"), time.time() + 60
while "Fra:" not in open(output).read() and time.time() < end:  # the child renders: past its own start
    time.sleep(0.05)
print("CHILD", job.process.pid, "running" if not job.done() else "ended", job._folder, flush=True)
if sys.argv[-1] == "crash":
    os.kill(os.getpid(), signal.SIGKILL)
"""


def process_gone(pid):
    """The process ended (gone, or a zombie its new parent has not reaped)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except OSError:
        return True


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the parent-death signal is Linux's")
@pytest.mark.parametrize("how", ["quit", "crash"])
def test_no_bake_outlives_blender(tmp_path, how):
    """A Blender that quits while its background bake renders kills it (atexit, which also removes its folder); one
    that is killed takes its child with it (the child's parent-death signal).  (A child whose Blender ended before
    the child's own start ends itself as it starts: its parent is not the one it was given.)"""
    script = tmp_path / "start_bake.py"
    script.write_text(QUIT_SCRIPT)
    addon = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "addon")
    package = os.environ.get("SPHRECT_PYTHON_PATH", "").split(os.pathsep)[0]
    run = subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", "--python", str(script), "--", addon, package,
                          str(tmp_path / "cache"), how], capture_output=True, text=True, timeout=WAIT_SECONDS)
    lines = [l for l in run.stdout.splitlines() if l.startswith("CHILD ")]
    assert lines, run.stdout[-2000:] + run.stderr[-2000:]
    pid, state, folder = lines[0].split()[1:]
    pid = int(pid)
    assert state == "running"  # (the child renders for a minute or more: it was, when its Blender ended)
    end = time.time() + WAIT_SECONDS
    try:
        while not process_gone(pid):
            assert time.time() < end, f"the bake's child {pid} outlived Blender ({how})"
            time.sleep(0.05)
        # Killed, not finished: the bake never written (a child left alone would write it and exit).
        assert not os.path.exists(os.path.join(folder, "world.npy"))
        if how == "quit":  # killed by the exit's handler, which removes its folder (the parent-death signal does not)
            assert not os.path.exists(folder)
    finally:
        if not process_gone(pid):
            os.kill(pid, signal.SIGKILL)
        shutil.rmtree(folder, ignore_errors=True)  # (left by the killed Blender)
    assert not (tmp_path / "cache").exists() or list((tmp_path / "cache").glob("*.npy")) == []


@pytest.mark.gui
@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="xvfb-run is not installed (apt install xvfb)")
def test_rendered_view_of_a_sky_in_a_window(tmp_path):
    """In a real window (xvfb): the view's first image is drawn while the sky's bake runs, its status saying so; the
    timer notices the bake's end and the view then shows the baked world; an edit of the sky shows the previous bake
    while the new one runs; leaving Rendered shading kills that child."""
    run = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", bpy.app.binary_path, "--factory-startup",
                          "--python", os.path.join(os.path.dirname(__file__), "gui_viewport_world_bake.py")],
                         capture_output=True, text=True, timeout=600,
                         env=dict(os.environ, SPHRECT_BAKE_CACHE=str(tmp_path)))
    lines = [l for l in run.stdout.splitlines() if l.startswith("GUI_RESULT ")]
    assert lines, run.stdout[-2000:] + run.stderr[-2000:]
    r = json.loads(lines[0][len("GUI_RESULT "):])
    print(r)
    assert "timeout" not in r and "error" not in r, r
    assert r["first_export"][0] == ["everything"]
    assert r["drawn_while_baking"] and "Baking world" in r["status_while_baking"], r
    assert not r["stand_in_environment"]  # the first view's stand-in: a constant
    assert "Baking world" not in r["landed_status"] and r["landed_export"][0] == ["world"], r
    assert r["edit_stand_in_is_previous_bake"], r
    assert r["child_after_solid"] == -signal.SIGKILL and r["sessions_after_solid"] == 0, r
