"""The add-on's modal path in Blender with a window (issue #39): progress, Esc.

Run by crates/python/tests/pytest.rs under a virtual X server:
    xvfb-run -a blender --factory-startup --enable-event-simulate --python check_modal.py -- ZIP

Operators invoked from the menu run on a worker thread: a window timer polls
the job, shows its progress (status bar, progress cursor) and Esc cancels it.
Here, driven by `bpy.app.timers` as a user's clicks would be:
- DLA Terrain is invoked as the Add menu does (`INVOKE_REGION_WIN` in the 3-D
  view) and runs modal; its job reports progress while it runs;
- Esc (an event simulated in the window, as if pressed) cancels it: the job
  ends cancelled and the scene's objects and meshes are those before;
- invoked again and left alone, it ends with the terrain in the scene.
Prints "ok   what" / "FAIL what" and quits with 1 on a failure.
"""
import importlib
import sys
import time

import bpy

ZIP = sys.argv[-1]
failures = []


def check(what, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {what} {detail}", flush=True)
    if not ok:
        failures.append(what)


bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
bpy.ops.preferences.addon_enable(module="asperity_addon")
engine = importlib.import_module("asperity_addon.engine")

# every job the operators start, to watch them from here
jobs = []
_init = engine.Job.__init__


def _recorded(self, fn):
    _init(self, fn)
    jobs.append(self)


engine.Job.__init__ = _recorded


def scene_state():
    return sorted(o.name for o in bpy.data.objects), sorted(m.name for m in bpy.data.meshes)


def invoke_terrain():
    """DLA Terrain as the Add menu invokes it, in the 3-D view's window region."""
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=window, area=area, region=region):
        return bpy.ops.mesh.asperity_dla_terrain("INVOKE_REGION_WIN", size=96, particles=60000, seed=5)


state = {}


def step_start_and_cancel():
    state["before"] = scene_state()
    r = invoke_terrain()
    check("invoked from the menu, it runs modal", r == {"RUNNING_MODAL"}, str(r))
    check("a job started on a worker thread", len(jobs) == 1 and not jobs[0].done())
    state["t0"] = time.monotonic()
    return "progress"


def step_progress():
    job = jobs[-1]
    done, total, message = job.progress
    if (done == 0 or total == 0) and not job.done() and time.monotonic() - state["t0"] < 60:
        return "progress"
    check("the job reports progress while it runs", done > 0 and total > 0 and not job.done(),
          f"{done}/{total} {message}")
    window = bpy.context.window_manager.windows[0]
    window.event_simulate(type="ESC", value="PRESS")
    window.event_simulate(type="ESC", value="RELEASE")
    state["t1"] = time.monotonic()
    return "cancelled"


def step_cancelled():
    job = jobs[-1]
    if not job.done() and time.monotonic() - state["t1"] < 60:
        return "cancelled"
    check("Esc stops the job", job.done() and isinstance(job.error, engine.Cancelled),
          f"{time.monotonic() - state['t1']:.2f} s after Esc, error {job.error!r}")
    state["t2"] = time.monotonic()
    return "unchanged"


def step_unchanged():
    # the modal handler ends on its next timer tick
    if time.monotonic() - state["t2"] < 0.5:
        return "unchanged"
    check("the cancelled run leaves the scene as it was", scene_state() == state["before"],
          f"{scene_state()} vs {state['before']}")
    r = invoke_terrain()
    check("invoked again, it runs modal", r == {"RUNNING_MODAL"}, str(r))
    state["t3"] = time.monotonic()
    return "finished"


def step_finished():
    # the modal handler adds the terrain on its first tick after the job ends
    added = "asperity DLA terrain" in bpy.data.objects
    if not added and time.monotonic() - state["t3"] < 120:
        return "finished"
    check("left alone, it ends with the terrain in the scene", added,
          f"{len(jobs)} jobs, error {jobs[-1].error!r}")
    return None


STEPS = {"start": step_start_and_cancel, "progress": step_progress, "cancelled": step_cancelled,
         "unchanged": step_unchanged, "finished": step_finished}
current = ["start"]


def tick():
    try:
        nxt = STEPS[current[0]]()
    except Exception as e:  # noqa: BLE001 - a failure, then quit
        check(f"step {current[0]}", False, repr(e))
        nxt = None
    if nxt is None:
        print(f"{len(failures)} failures", flush=True)
        bpy.ops.wm.quit_blender()
        return None
    current[0] = nxt
    return 0.05


bpy.app.timers.register(tick, first_interval=1.0)
