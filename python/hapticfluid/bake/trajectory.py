# SPDX-License-Identifier: GPL-3.0-or-later
"""The probe's motion for a bake: rigid transforms keyed at (possibly fractional) frames.

A :class:`Trajectory` holds keys ``(frame, 4x4 matrix)`` in world metres. Between keys the
translation and scale are interpolated linearly and the rotation by slerp (shortest arc);
before the first key and after the last the nearest key holds. Velocities over a substep are
differences of the poses at its two ends, so a bake is exactly reproducible from the keys.

Units: translations in metres, frames in frames (the bake's fps turns them into seconds),
velocities in m/s and angular velocities in rad/s (world axes).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from typing import Iterable, List, Sequence, Tuple

import numpy as np

from hapticfluid import InvalidArgumentError


@dataclass(frozen=True)
class Pose:
    """A rigid transform plus scale: world position (m), unit quaternion (w, x, y, z), scale."""

    translation: np.ndarray  # (3,) m
    rotation: np.ndarray  # (4,) unit quaternion w, x, y, z
    scale: np.ndarray  # (3,) dimensionless

    def matrix(self) -> np.ndarray:
        """The 4x4 matrix translation * rotation * scale."""
        m = np.eye(4)
        m[:3, :3] = quat_to_matrix(self.rotation) * self.scale[np.newaxis, :]
        m[:3, 3] = self.translation
        return m


@dataclass(frozen=True)
class Motion:
    """The probe during one substep: its pose at the substep's end and its mean velocities."""

    pose: Pose
    velocity: np.ndarray  # (3,) m/s
    angular_velocity: np.ndarray  # (3,) rad/s, world axes


def quat_to_matrix(q: Sequence[float]) -> np.ndarray:
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def matrix_to_quat(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method), w >= 0."""
    t = np.trace(r)
    if t > 0:
        s = 2.0 * math.sqrt(t + 1.0)
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = [(r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s]
    q = np.asarray(q, dtype=float)
    q /= np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ])


def slerp(a: np.ndarray, b: np.ndarray, t: float) -> np.ndarray:
    """Spherical interpolation of unit quaternions along the shorter arc."""
    d = float(np.dot(a, b))
    if d < 0.0:
        b, d = -b, -d
    if d > 0.9995:  # nearly equal: normalised lerp is exact to rounding
        q = a + t * (b - a)
        return q / np.linalg.norm(q)
    theta = math.acos(min(d, 1.0))
    s = math.sin(theta)
    return (math.sin((1.0 - t) * theta) / s) * a + (math.sin(t * theta) / s) * b


def decompose(matrix: Sequence[Sequence[float]]) -> Pose:
    """Split a 4x4 affine matrix (rotation * scale, no shear) into a Pose."""
    m = np.asarray(matrix, dtype=float)
    if m.shape != (4, 4) or not np.all(np.isfinite(m)):
        raise InvalidArgumentError(f"a probe transform must be a finite 4x4 matrix, got shape {m.shape}")
    if not np.allclose(m[3], (0.0, 0.0, 0.0, 1.0), atol=1e-9):
        raise InvalidArgumentError(f"a probe transform's last row must be (0, 0, 0, 1), got {m[3].tolist()}")
    linear = m[:3, :3]
    with np.errstate(over="ignore"):  # axes near 1e308 long: an inf length, refused below
        scale = np.linalg.norm(linear, axis=0)
    if not np.all(np.isfinite(scale)):
        raise InvalidArgumentError(f"a probe transform's axes are too long for a float: scale {scale.tolist()}; "
                                   "give a matrix whose scale is a finite number")
    if np.any(scale < 1e-12):
        raise InvalidArgumentError(f"a probe transform has a zero scale: {scale.tolist()}")
    rot = linear / scale[np.newaxis, :]
    skew = float(np.abs(rot.T @ rot - np.eye(3)).max())
    if skew > 1e-4:  # a sheared matrix would come back as a different shape: refuse, never alter it
        raise InvalidArgumentError(
            f"a probe transform is sheared (its axes are not perpendicular: |R^T R - I| = {skew:.3g}), which "
            "the keyed motion (rotation, scale, translation) cannot hold; apply the parent's non-uniform "
            "scale or unparent the probe")
    if np.linalg.det(rot) < 0:  # a mirror: keep a proper rotation and flip x's scale
        scale[0] = -scale[0]
        rot[:, 0] = -rot[:, 0]
    return Pose(translation=m[:3, 3].copy(), rotation=matrix_to_quat(rot), scale=scale)


class Trajectory:
    """Piecewise linear (translation, scale) / slerp (rotation) motion through keyed transforms."""

    def __init__(self, keys: Iterable[Tuple[float, Sequence[Sequence[float]]]]):
        items: List[Tuple[float, Pose]] = []
        for frame, matrix in keys:
            f = float(frame)
            if not math.isfinite(f):
                raise InvalidArgumentError(f"a probe key's frame must be finite, got {frame!r}")
            items.append((f, decompose(matrix)))
        if not items:
            raise InvalidArgumentError("the probe trajectory needs at least one key (frame, transform)")
        items.sort(key=lambda kv: kv[0])
        for (fa, _), (fb, _) in zip(items, items[1:]):
            if fb == fa:
                raise InvalidArgumentError(f"two probe keys at frame {fa:g}: each frame may be keyed once")
        self._frames = np.array([f for f, _ in items])
        self._poses = [p for _, p in items]

    @classmethod
    def constant(cls, matrix: Sequence[Sequence[float]]) -> "Trajectory":
        return cls([(0.0, matrix)])

    @property
    def keys(self) -> List[Tuple[float, np.ndarray]]:
        return [(float(f), p.matrix()) for f, p in zip(self._frames, self._poses)]

    @property
    def frames(self) -> np.ndarray:
        return self._frames.copy()

    @property
    def poses(self) -> List[Pose]:
        return list(self._poses)

    def pose(self, frame: float) -> Pose:
        """The pose at a (fractional) frame."""
        f = self._frames
        if frame <= f[0]:
            return self._poses[0]
        if frame >= f[-1]:
            return self._poses[-1]
        i = int(np.searchsorted(f, frame, side="right")) - 1
        if frame == f[i]:  # exactly a key: that key (an interpolation at t = 0 could round)
            return self._poses[i]
        a, b = self._poses[i], self._poses[i + 1]
        t = (frame - f[i]) / (f[i + 1] - f[i])
        return Pose(
            translation=a.translation + t * (b.translation - a.translation),
            rotation=slerp(a.rotation, b.rotation, t),
            scale=a.scale + t * (b.scale - a.scale),
        )

    def keys_between(self, frame_a: float, frame_b: float) -> List[Tuple[float, Pose]]:
        """The keys that every pose from frame_a to frame_b (inclusive) is computed from: the last
        key at or before frame_a, every key in between, and the first key at or after frame_b
        (fewer where the range lies before the first key or after the last). Two trajectories
        whose keys_between agree give the same poses over the range, to the bit."""
        f = self._frames
        lo = max(0, int(np.searchsorted(f, frame_a, side="right")) - 1)
        hi = min(len(f) - 1, int(np.searchsorted(f, frame_b, side="left")))
        return [(float(f[i]), self._poses[i]) for i in range(lo, max(lo, hi) + 1)]

    def digest_between(self, frame_a: float, frame_b: float) -> str:
        """SHA-256 (hex) of keys_between: the frame numbers and the poses' float64 values."""
        h = hashlib.sha256()
        for frame, pose in self.keys_between(frame_a, frame_b):
            h.update(np.array([frame], dtype=np.float64).tobytes())
            for part in (pose.translation, pose.rotation, pose.scale):
                h.update(np.ascontiguousarray(part, dtype=np.float64).tobytes())
        return h.hexdigest()

    def motion(self, frame_a: float, frame_b: float, dt_s: float) -> Motion:
        """The pose at frame_b and the mean velocities from frame_a to frame_b (dt_s seconds)."""
        pa, pb = self.pose(frame_a), self.pose(frame_b)
        velocity = (pb.translation - pa.translation) / dt_s
        dq = quat_mul(pb.rotation, pa.rotation * np.array([1.0, -1.0, -1.0, -1.0]))
        if dq[0] < 0:
            dq = -dq
        sin_half = float(np.linalg.norm(dq[1:]))
        if sin_half < 1e-15:
            omega = np.zeros(3)
        else:
            angle = 2.0 * math.atan2(sin_half, float(dq[0]))
            omega = dq[1:] / sin_half * (angle / dt_s)
        return Motion(pose=pb, velocity=velocity, angular_velocity=omega)
