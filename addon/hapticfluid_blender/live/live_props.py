# SPDX-License-Identifier: GPL-3.0-or-later
"""The live session's settings and read-only stats, stored on the scene as ``scene.hapticfluid_live``.

The domain, probe and smoke source are the objects holding those roles (Physics tab, read through
``roles.settings_of(scene)``), the same for the bake and the live session.
Defaults of the haptic settings come from the engine (``hapticfluid.HapticSessionSettings()``),
so the add-on and the Python API behave alike; without the package the properties register with
no default (no session can start then, and the panel says why).
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, PointerProperty, \
    StringProperty


def _engine_defaults():
    try:
        import hapticfluid

        defaults = {k: getattr(v, "name", v) for k, v in hapticfluid.HapticSessionSettings().to_dict().items()}
    except ImportError:  # (an engine enum by its name: 'amplified')
        return {}
    defaults["workspace_scale"] = defaults["workspace_scale"][0]  # the same on every axis: one number here
    return defaults


_DEFAULTS = _engine_defaults()


def _gesture_items():
    """The simulated hand's gestures (hapticfluid.hand_gestures): (IDENTIFIER, Name, description)."""
    try:
        from hapticfluid import hand_gestures

        described = hand_gestures.DESCRIPTIONS
    except ImportError:
        described = {"rest": "The hand rests at the middle of the workspace"}
    return tuple((name.upper(), name.capitalize(), text) for name, text in described.items())


def _default(name):
    return {"default": _DEFAULTS[name]} if _DEFAULTS.get(name) is not None else {}


# What follows the object in Mouse and Timeline mode (also docs/ARCHITECTURE.md, Live session).
ROTATION_NOTE = ("The object's location and rotation drive the fluid; its scale stays what it was at Start "
                 "(a scale change applies at the next Start)")
CPU_SHARE_ITEMS = (
    ("AUTO", "Auto", "Viewport First when the mouse or the timeline moves the probe (the viewport is what you "
                     "follow), Equal with a Falcon (what the hand feels needs the simulation's rate)"),
    ("VIEWPORT", "Viewport First", "The simulation runs at a lower priority and at most 30 steps a second: the "
                                   "viewport keeps its pace, the simulation steps in what the drawing leaves "
                                   "(2 cores, 32^3: about 80% of the redraws without a session, 20 steps/s)"),
    ("EQUAL", "Equal", "The simulation and the drawing share the cores equally (2 cores, 32^3: about 60% of the "
                       "redraws without a session, 80-90 steps/s)"),
)

DEVICE_ITEMS = (
    ("MOUSE", "Mouse / Transform", "No device: the probe object's transform drives the fluid; grab it (G), "
                                   "turn it (R) or move it any way Blender allows. " + ROTATION_NOTE),
    ("TIMELINE", "Timeline", "The probe's animation drives the fluid while the timeline plays (Record re-records "
                             "it as it plays, at the frames played). " + ROTATION_NOTE),
    ("FALCON", "Falcon", "A Novint Falcon: the probe follows its grip and the force goes to the handle"),
    ("SIMULATED_FALCON", "Simulated Falcon", "The Falcon driver on a simulated Falcon held by a simulated hand "
                                             "(demos and tests, no hardware)"),
)


def _stat(name, description, unit="NONE", precision=1):
    return FloatProperty(name=name, description=description, default=0.0, unit=unit, precision=precision)


class HapticFluidLiveSettings(bpy.types.PropertyGroup):
    device: EnumProperty(name="Device", items=DEVICE_ITEMS, default="MOUSE",
                         description="What moves the probe during the live session")
    auto_resolution: BoolProperty(
        name="Auto Resolution", default=True,
        description="Preview resolution by the GPU: 32 cells on a software renderer (llvmpipe), 64 on a hardware GPU")
    resolution: IntProperty(name="Preview Resolution", default=32, min=8, max=512, soft_max=128,
                            description="Cells along the domain's longest edge during the live session "
                                        "(the bake has its own)")
    cpu_share: EnumProperty(
        name="CPU Share", items=CPU_SHARE_ITEMS, default="AUTO",
        description="Who goes first when the simulation and Blender's drawing both want the cores, on a CPU GL "
                    "device (no usable GPU; no effect on a GPU)")
    auto_workspace: BoolProperty(
        name="Fit Workspace", default=True,
        description="Map the device's workspace onto the domain: uniform scale so it fits, its middle at the "
                    "domain's centre")
    workspace_scale: FloatProperty(name="Workspace Scale", min=-1000.0, max=1000.0, soft_min=0.1, soft_max=100.0,
                                   description="Domain metres per device metre (Falcon modes, Fit Workspace off)",
                                   **_default("workspace_scale"))
    workspace_offset: FloatVectorProperty(name="Workspace Offset", size=3, subtype="TRANSLATION", unit="LENGTH",
                                          description="World position (m) of the device's origin (Falcon modes, "
                                                      "Fit Workspace off)")
    auto_force_gain: BoolProperty(
        name="Derive Gain", default=True,
        description="Force gain the device can render for this probe, fluid and workspace scale (the engine "
                    "derives it; Stats shows why); off: Force Gain")
    force_gain: FloatProperty(name="Force Gain", default=1.0, min=0.0, max=1e6, soft_max=1000.0,
                              description="Device newtons per fluid newton (Derive Gain off); above what the "
                                          "device renders passively, Start refuses it unless Allow Unsafe Gain is on")
    allow_unsafe_gain: BoolProperty(
        name="Allow Unsafe Gain", default=False,
        description="Accept a Force Gain above what the device renders passively (Start asks to confirm): the "
                    "rendering may then put energy into the hand, as oscillation or a kick")
    feel: EnumProperty(
        name="Feel", default=str(_DEFAULTS.get("feel", "amplified")).upper(),
        items=(("AMPLIFIED", "Amplified", "The largest gain the rendering holds passively (the engine derives it; "
                                          "Stats shows why): a weak fluid such as air is felt"),
               ("PHYSICAL", "Physical 1:1", "The fluid's own newtons on the hand (gain 1)")),
        description="What the hand feels of the fluid's force when the gain is derived")
    max_force: FloatProperty(name="Max Force", default=4.0, min=0.01, max=8.0, unit="NONE",
                             description="Largest force sent to the device (N); the Falcon's limit is 8 N")
    bandwidth_ratio: FloatProperty(name="Filter Bandwidth", min=0.01, max=10.0,
                                   description="Force low-pass cutoff as a fraction of the measured simulation "
                                               "rate (dimensionless)", **_default("bandwidth_ratio"))
    prediction: BoolProperty(name="Prediction",
                             description="Update the force between simulation frames with a fitted drag model",
                             **_default("prediction"))
    hand_gesture: EnumProperty(name="Hand Gesture", items=_gesture_items(), default="REST",
                               description="What the simulated hand does with the Simulated Falcon's grip after "
                                           "homing (the probe follows it)")
    feel_playback: BoolProperty(name="Feel Playback", default=True,
                                description="Falcon modes: while the timeline plays the probe's keys and Record is "
                                            "off, the fluid's probe follows the keys and the device guides the grip "
                                            "along them (a spring the hand can resist), so the hand feels the "
                                            "existing motion; Record hands the probe back to the hand")
    firmware_path: StringProperty(name="Falcon Firmware", subtype="FILE_PATH", default="",
                                  description="Novint's firmware file (nvent_firmware.bin), uploaded when the Falcon "
                                              "runs none (after power-on); empty: it must already run")
    record_rate: FloatProperty(name="Record Rate", default=24.0, min=1.0, max=1000.0,
                               description="Keys per second of performance recorded into the probe's action (Hz)")
    density_scale: FloatProperty(name="Smoke Density", default=20.0, min=0.0, max=10000.0,
                                 description="Viewport extinction per unit density per metre (1/m)")
    show_temperature: BoolProperty(name="Temperature Colour", default=False,
                                   description="Colour the viewport smoke by temperature")
    # Live state and stats, written by the session (not settings).
    is_running: BoolProperty(name="Running", default=False, description="A live session runs")
    is_recording: BoolProperty(name="Recording", default=False, description="The probe's motion is being keyed")
    status: StringProperty(name="Status", default="", description="What the live session does or why it ended")
    resolution_used: IntProperty(name="Resolution", default=0, description="Cells along the longest edge in use")
    device_used: StringProperty(name="Device", default="",
                                description="The simulation's backend (GPU or CPU) and what it runs on")
    sim_rate_hz: _stat("Simulation", "Simulation steps per second (Hz)")
    haptic_rate_hz: _stat("Haptic", "Haptic loop periods per second (Hz)", precision=0)
    jitter_p99_ms: _stat("Jitter p99", "99th percentile of the haptic period's deviation (ms)", precision=3)
    latency_p50_ms: _stat("Latency p50", "Median device pose -> force latency (ms)")
    latency_p99_ms: _stat("Latency p99", "99th percentile device pose -> force latency (ms)")
    force_n: _stat("Fluid Force", "Magnitude of the fluid force on the probe (N)", precision=4)
    device_force_n: _stat("Device Force", "Magnitude of the force commanded to the device (N)", precision=3)
    force_gain_used: _stat("Gain", "Device newtons per fluid newton in use", precision=3)
    force_gain_reason: StringProperty(name="Gain Reason", default="", description="How the force gain was chosen")
    device_state: StringProperty(name="Device", default="", description="Device name, homed, buttons")
    realtime: BoolProperty(name="Real-time Priority", default=False,
                           description="The haptic thread got real-time (SCHED_FIFO) priority")
    scheduling: StringProperty(name="Scheduling", default="", description="Why real-time priority was not granted")


_LIVE_STATE = ("is_running", "is_recording")


@bpy.app.handlers.persistent
def clear_stale_live_state(_filepath=None):
    """load_post handler: a file saved during a live session keeps is_running; no session of a
    file just opened runs."""
    for scene in bpy.data.scenes:
        live = getattr(scene, "hapticfluid_live", None)
        if live is not None and (live.is_running or live.is_recording):
            for name in _LIVE_STATE:
                setattr(live, name, False)
            live.status = "the live session of this file ended when it was saved or closed"


def attach():
    bpy.types.Scene.hapticfluid_live = PointerProperty(type=HapticFluidLiveSettings)


def detach():
    del bpy.types.Scene.hapticfluid_live
