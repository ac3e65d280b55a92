# SPDX-License-Identifier: GPL-3.0-or-later
"""Record in a live session: a take of the probe object's motion, and the keys written from it.

A ``Recording`` collects (frame, location, rotation) samples while Record is on: at every tick
the object's pose (``sample``) and, in Falcon modes, the hand's path between ticks from the
session's trace (``add_trace``). Frame-locked (the timeline plays) a sample's frame is the frame
played when it was performed, and a punch-in mutes the object's location and rotation F-curves
until Record-off. ``keys()`` ends the take (the mutes undone) and resamples it at the record rate
(``resample``); ``write_keys`` puts those keys into the object's action, every key outside the
take's frames left as it was, bit for bit.

No engine and no operator here: the live controller (live_session.py) drives it from its tick on
Blender's main thread.
"""

import math
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

TRACE_SAMPLES_PER_KEY = 4              # of the trace, Record keeps this many poses per key interval


def rotation_path_of(obj) -> str:
    """The F-curve path of the object's rotation in its rotation mode."""
    return {"QUATERNION": "rotation_quaternion", "AXIS_ANGLE": "rotation_axis_angle"}.get(
        obj.rotation_mode, "rotation_euler")


@dataclass
class Recording:
    obj_name: str
    rotation_path: str
    start_frame: float
    fps: float
    interval_s: float
    t0: float
    # Frame-locked (the timeline plays): a sample's frame is the frame played when it was performed
    # (clock_frames maps the clock to the played frame), and Record-off keys the frame then played
    # (B), so the take replaces exactly the frames A..B that played. Otherwise the frame is
    # start_frame + elapsed x fps (a performance recorded over a still timeline).
    frame_locked: bool = False
    clock_frames: List[Tuple[float, float]] = field(default_factory=list)  # (clock s, frame played)
    muted: List[Tuple[str, int, bool]] = field(default_factory=list)  # (path, index, mute before) punched in
    trace_t: float = -math.inf         # clock time of the last trace pose kept (s)
    looped: bool = False               # the timeline jumped back: samples after it are not kept
    # (frame, location, rotation) of the object at every tick: the motion performed, as Blender
    # knew it (a drag moves the object once per pass of the event loop, as often as it redraws)
    samples: List[Tuple[float, Tuple[float, ...], Tuple[float, ...]]] = field(default_factory=list)

    @classmethod
    def start(cls, obj, scene, now: float, record_rate: float, frame_locked: bool, punch_in: bool) -> "Recording":
        """A take of ``obj`` from clock time ``now`` at ``record_rate`` keys per second, starting at
        the scene's current frame (A). ``punch_in`` (frame-locked only) mutes the object's location
        and rotation F-curves until keys() so the performance, not the existing keys, moves it."""
        path = rotation_path_of(obj)
        r = cls(obj_name=obj.name, rotation_path=path, start_frame=float(scene.frame_current_final),
                fps=scene.render.fps / scene.render.fps_base, interval_s=1.0 / record_rate, t0=now,
                frame_locked=frame_locked)
        if frame_locked:
            r.clock_frames.append((now, r.start_frame))
            if punch_in:
                r.muted = mute_channels(obj, ("location", path))
        return r

    def frame_at(self, t: float) -> Optional[float]:
        """The frame a pose performed at clock time t belongs to; None before the take."""
        if t < self.t0:
            return None
        if not self.frame_locked:
            return self.start_frame + (t - self.t0) * self.fps
        pairs = self.clock_frames
        if not pairs or t <= pairs[0][0]:
            return self.start_frame
        for (ta, fa), (tb, fb) in zip(pairs, pairs[1:]):
            if t <= tb:
                return fa + (fb - fa) * (t - ta) / (tb - ta) if tb > ta else fb
        return pairs[-1][1]

    def mark_frame(self, t: float, played: float) -> None:
        """Frame-locked: ``played``, the frame playing at clock time t (kept when it moved on). A
        frame before the last one (playback looped at the end frame, or the user scrubbed back)
        ends the take's samples: the keys cover the frames played once, in order."""
        last = self.clock_frames[-1][1] if self.clock_frames else -math.inf
        if played < last:
            self.looped = True
        elif played > last:
            self.clock_frames.append((t, played))

    def sample(self, now: float, played: float, obj) -> None:
        """The object's pose at clock time ``now`` (``played``: the scene's frame then), at the frame
        played (frame-locked) or at start_frame + elapsed x fps; one sample per frame at most."""
        if self.frame_locked:
            self.mark_frame(now, played)
            if self.looped:
                return
            frame = played
        else:
            frame = self.start_frame + (now - self.t0) * self.fps
        if self.samples and frame <= self.samples[-1][0]:
            return
        self.samples.append((frame, tuple(obj.location), tuple(getattr(obj, self.rotation_path))))

    def add_trace(self, times, origins, obj) -> None:
        """Falcon modes: the device's poses since the last tick (clock times ``times``, one per haptic
        period; ``origins``, where the engine put the probe for each, world m) as samples of the
        object's location (less its parent's offset), TRACE_SAMPLES_PER_KEY per key interval, at the
        frames they were performed at, so the keys follow the hand's path, not the straight line
        between ticks. The rotation is the object's (Falcon modes keep the start rotation)."""
        world_now = obj.matrix_world.translation
        parent = tuple(world_now[i] - obj.location[i] for i in range(3))  # a parent's translation
        rotation = tuple(getattr(obj, self.rotation_path))
        spacing = self.interval_s / TRACE_SAMPLES_PER_KEY
        for t, w in zip(times, origins):
            t = float(t)
            if t < self.trace_t + spacing:
                continue
            frame = self.frame_at(t)
            if frame is None or (self.samples and frame <= self.samples[-1][0]):
                continue
            self.trace_t = t
            self.samples.append((frame, tuple(float(w[i]) - parent[i] for i in range(3)), rotation))

    def keys(self, obj) -> List[Tuple[float, Tuple[float, ...], Tuple[float, ...]]]:
        """Ends the take: the muted F-curves of ``obj`` as they were, then the take's keys at the
        record rate (resample; frame-locked, one at B too), or [] when nothing was performed (or,
        frame-locked, no frame played)."""
        restore_mutes(obj, self.muted)
        if not self.samples or (self.frame_locked and len(self.samples) < 2):
            return []
        return resample(self.samples, self.interval_s * self.fps,
                        quaternion=self.rotation_path == "rotation_quaternion", end=self.frame_locked)


def mute_channels(obj, paths) -> List[Tuple[str, int, bool]]:
    """Mutes the object's F-curves of those paths (so playback leaves the channels to the
    performance); returns (path, index, mute before) to restore."""
    data = obj.animation_data
    if data is None or data.action is None:
        return []
    muted = []
    for fc in object_fcurves(obj):
        if fc.data_path in paths:
            muted.append((fc.data_path, fc.array_index, fc.mute))
            fc.mute = True
    return muted


def restore_mutes(obj, muted):
    if not muted or obj.animation_data is None or obj.animation_data.action is None:
        return
    fcurves = object_fcurves(obj)
    for path, index, before in muted:
        fc = fcurves.find(path, index=index)
        if fc is not None:
            fc.mute = before


def resample(samples, frames_per_key, quaternion=False, end=False):
    """(frame, location, rotation) samples at uneven frames -> the same path at frames
    samples[0] + k * frames_per_key up to the last sample's frame (end: and at the last sample's
    own frame, when the grid misses it): linear between the two samples around each, a quaternion
    rotation (w, x, y, z) normalized-linearly on the shorter arc."""
    if not samples:
        return []
    out = []
    first, last = samples[0][0], samples[-1][0]
    frames = []
    k = 0
    while first + k * frames_per_key <= last + 1e-9:
        frames.append(first + k * frames_per_key)
        k += 1
    if end and last - frames[-1] > 1e-6:
        frames.append(last)
    i = 0
    for frame in frames:
        while i + 1 < len(samples) - 1 and samples[i + 1][0] < frame:
            i += 1
        a = samples[i]
        b = samples[min(i + 1, len(samples) - 1)]
        span = b[0] - a[0]
        w = 0.0 if span <= 0.0 else min(1.0, max(0.0, (frame - a[0]) / span))
        location = tuple(x + w * (y - x) for x, y in zip(a[1], b[1]))
        rb = b[2]
        if quaternion and sum(x * y for x, y in zip(a[2], rb)) < 0.0:
            rb = tuple(-y for y in rb)  # the shorter way round
        rotation = tuple(x + w * (y - x) for x, y in zip(a[2], rb))
        if quaternion:
            norm = math.sqrt(sum(c * c for c in rotation)) or 1.0
            rotation = tuple(c / norm for c in rotation)
        out.append((frame, location, rotation))
    return out


# What a key is besides its point: kept, with co and handles, for every key outside a take.
_KEY_FIELDS = ("handle_left_type", "handle_right_type", "interpolation", "easing", "back", "amplitude", "period",
               "type")


def key_state(point):
    """A keyframe point as plain values: co, handle_left, handle_right, then _KEY_FIELDS."""
    return (tuple(point.co), tuple(point.handle_left), tuple(point.handle_right)) + tuple(
        getattr(point, name) for name in _KEY_FIELDS)


def write_keys(obj, rotation_path, samples):
    """Keys location and rotation at each (frame, location, rotation) sample into the object's
    action, first removing the keys of those channels within the samples' frame range. Keys
    outside the range keep their co, handles, handle types and interpolation bit for bit: Blender
    recomputes every automatic handle of a curve when keys are added (fc.update()), which would
    move the handles of the keys around the take, so theirs are put back as they were."""
    lo = min(s[0] for s in samples) - 1e-4
    hi = max(s[0] for s in samples) + 1e-4
    channels = (("location", 1), (rotation_path, 2))
    data = obj.animation_data
    fcurves = object_fcurves(obj) if data is not None and data.action is not None else None
    kept = {}
    for path, slot in channels:
        for index in range(len(samples[0][slot])):
            fc = fcurves.find(path, index=index) if fcurves is not None else None
            if fc is not None:
                kept[(path, index)] = [key_state(p) for p in fc.keyframe_points if not lo <= p.co.x <= hi]
            else:  # makes the action, its slot and the F-curves as Blender does (a key inside the range)
                obj.keyframe_insert(path, frame=samples[0][0])
                fcurves = object_fcurves(obj)
    for path, slot in channels:
        for index in range(len(samples[0][slot])):
            fc = fcurves.find(path, index=index)
            points = fc.keyframe_points
            for k in reversed(range(len(points))):
                if lo <= points[k].co.x <= hi:
                    points.remove(points[k], fast=True)
            for s in samples:
                points.insert(s[0], s[slot][index], options={"FAST"})
            fc.update()
            outside = [p for p in points if not lo <= p.co.x <= hi]
            before = kept.get((path, index), [])
            if len(outside) != len(before):  # keys made by keyframe_insert above lie inside the range
                raise RuntimeError(f"{path}[{index}]: {len(before)} keys outside frames {lo:.4g}..{hi:.4g} "
                                   f"became {len(outside)}")
            for p, state in zip(outside, before):
                _put_back(p, state)


def _put_back(point, state):
    co, left, right = state[:3]
    for name, value in zip(_KEY_FIELDS, state[3:]):
        if getattr(point, name) != value:
            setattr(point, name, value)
    point.co = co
    point.handle_left = left
    point.handle_right = right


def object_fcurves(obj):
    """The F-curves animating the object: on the action up to Blender 4.x, in the action slot's
    channel bag from 4.4 (only there in 5.0)."""
    data = obj.animation_data
    if hasattr(data.action, "fcurves"):
        return data.action.fcurves
    from bpy_extras import anim_utils

    return anim_utils.action_get_channelbag_for_slot(data.action, data.action_slot).fcurves
