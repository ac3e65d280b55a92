# SPDX-License-Identifier: GPL-3.0-or-later
"""assembly.build, the one place engine objects are made (the bake, the add-on's live session, the
demo and the haptic command line): a scene description in, the Simulation with its source and
probe in place and, given a device, the HapticSession over it out; a refused part is the engine's
own error, and the simulation made for it is closed."""

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import assembly, meshes


def settings(resolution=16):
    return assembly.fluid_settings((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), resolution, {"fluid_density": 1000.0})


def moved(position, scale=1.0):
    m = np.eye(4)
    m[:3, :3] *= scale
    m[:3, 3] = position
    return m


def test_build_places_the_source_and_the_probe_and_makes_no_session_without_a_device():
    source = assembly.Source(centre=(0.5, 0.5, 0.2), radius=0.1, density=2.0, temperature=3.0)
    probe = assembly.Probe("sphere", moved((0.5, 0.5, 0.6), scale=2.0), radius=0.05, velocity=(0.1, 0.0, 0.0))
    sim, session = assembly.build(assembly.SceneDescription(settings(), source=source, probe=probe))
    with sim:
        assert session is None
        assert sim.resolution == (16, 16, 16)
        s = sim.smoke_source
        assert s["kind"] == "sphere" and s["density"] == 2.0 and s["temperature"] == 3.0
        np.testing.assert_allclose(s["centre"], (0.5, 0.5, 0.2), atol=1e-7)
        p = sim.probe
        assert p["kind"] == "sphere" and p["radius"] == pytest.approx(0.1)  # 0.05 at the matrix's scale 2
        np.testing.assert_allclose(p["centre"], (0.5, 0.5, 0.6), atol=1e-7)
        np.testing.assert_allclose(p["velocity"], (0.1, 0.0, 0.0), atol=1e-7)


def test_a_source_dict_of_a_scene_is_a_source():
    """The add-on's source_dict (a sphere has no "shape" key) and a mesh's keys map onto Source."""
    vertices, triangles = meshes.box((0.2, 0.2, 0.2))
    mesh = {"shape": "mesh", "vertices": vertices, "triangles": triangles, "matrix": moved((0.5, 0.5, 0.3)),
            "density": 1.0, "temperature": 0.0}
    sim, _ = assembly.build(assembly.SceneDescription(settings(), source=assembly.Source(**mesh)))
    with sim:
        assert sim.smoke_source["kind"] == "mesh"
        assembly.place_source(sim, assembly.Source(**{**mesh, "matrix": moved((0.5, 0.5, 0.4))}))  # only moved
        np.testing.assert_allclose(np.asarray(sim.smoke_source["transform"])[:3, 3], (0.5, 0.5, 0.4), atol=1e-7)


def test_build_makes_the_session_over_the_simulation_not_started():
    sim, session = assembly.build(assembly.SceneDescription(settings()), hf.null_device(),
                                  hf.HapticSessionSettings(workspace_scale=2.0, probe_radius=0.15))
    with sim:
        assert isinstance(session, hf.HapticSession) and session.state == "idle"
        assert session.settings.workspace_scale == (2.0, 2.0, 2.0)
        assert sim.probe["kind"] == "sphere" and sim.probe["radius"] == pytest.approx(0.15)  # the session's probe


@pytest.mark.parametrize("part", ["source", "probe", "session"])
def test_a_refused_part_is_the_engines_error_and_closes_the_simulation(part, monkeypatch):
    made = []

    class Watched(hf.Simulation):
        def __init__(self, *args):
            super().__init__(*args)
            made.append(self)

    monkeypatch.setattr(hf, "Simulation", Watched)
    vertices, triangles = meshes.box((0.2, 0.2, 0.2))
    scene = assembly.SceneDescription(
        settings(),
        source=assembly.Source(centre=(5.0, 5.0, 5.0), radius=0.1) if part == "source" else None,
        probe=assembly.Probe("mesh", moved((0.5, 0.5, 0.5)), vertices=vertices, triangles=triangles[:-1])
        if part == "probe" else None)
    expected = {"source": hf.InvalidArgumentError, "probe": hf.MeshNotClosedError,
                "session": hf.InvalidArgumentError}[part]
    session_settings = hf.HapticSessionSettings(probe_radius=2.0) if part == "session" else None
    with pytest.raises(expected, match="smoke source|closed|probe"):
        assembly.build(scene, hf.null_device() if part == "session" else None, session_settings)
    assert len(made) == 1 and made[0].closed, "the simulation made for the scene is closed"
