"""hapticfluid.farm: the job writer (paths relative to the shared root, names the job files
declare), frame chunks, the bake task's resume decision and the shipped job files."""

import json
import re
import sys
from pathlib import Path

import pytest
import yaml

from hapticfluid import farm
from hapticfluid.bake.cache import checkpoint_path
from hapticfluid.farm import bake_step

ADDON = Path(__file__).resolve().parents[2] / "addon"


def _job(root: Path, **kw) -> farm.FarmJob:
    args = dict(shared_root=str(root), scene_file=str(root / "shots" / "a.json"), cache_dir=str(root / "cache" / "a"),
                output_dir=str(root / "renders" / "a"), frame_start=1, frame_end=48, resolution=128, chunk_size=10)
    args.update(kw)
    return farm.FarmJob(**args)


def _template():
    return yaml.safe_load(farm.OPENJD_TEMPLATE.read_text())


def test_the_template_is_a_2023_09_job_with_a_bake_step_and_chunked_render_step_after_it():
    t = _template()
    assert t["specificationVersion"] == "jobtemplate-2023-09" and t["extensions"] == ["TASK_CHUNKING"]
    bake, render = t["steps"]
    assert bake["name"] == "Bake" and "parameterSpace" not in bake  # one task
    assert render["dependencies"] == [{"dependsOn": "Bake"}]
    (chunk,) = render["parameterSpace"]["taskParameterDefinitions"]
    assert chunk["type"] == "CHUNK[INT]" and chunk["range"] == "{{Param.Frames}}"
    assert chunk["chunks"] == {"defaultTaskCount": "{{Param.ChunkSize}}", "rangeConstraint": "CONTIGUOUS"}
    assert "{{Task.Param.Frames}}" in render["script"]["actions"]["onRun"]["args"]


def test_openjd_values_are_relative_to_the_shared_root_and_are_template_parameters(tmp_path):
    job = _job(tmp_path, python_path="/opt/hf/python:/opt/hf/addon", render_size=(640, 360))
    written = farm.write_openjd_job(job, tmp_path / "jobs" / "a")
    values = json.loads((tmp_path / "jobs" / "a" / "parameters.json").read_text())
    assert values == {"SceneFile": "shots/a.json", "CacheDir": "cache/a", "OutputDir": "renders/a", "Resolution": 128,
                      "Frames": "1-48", "ChunkSize": 10, "PythonPath": "/opt/hf/python:/opt/hf/addon",
                      "RenderWidth": 640, "RenderHeight": 360}
    declared = {p["name"]: p for p in _template()["parameterDefinitions"]}
    assert set(values) <= set(declared) and "SharedRoot" in declared
    assert all("default" in p for name, p in declared.items() if name not in values and name != "SharedRoot")
    bundle = json.loads((tmp_path / "jobs" / "a" / "parameter_values.json").read_text())
    assert {v["name"]: v["value"] for v in bundle["parameterValues"]} == values
    assert (tmp_path / "jobs" / "a" / "template.yaml").read_text() == farm.OPENJD_TEMPLATE.read_text()
    assert "openjd run jobs/a/template.yaml" in written["command"]
    assert "-p file://jobs/a/parameters.json" in written["command"]


def test_flamenco_settings_are_relative_and_declared_by_the_job_type(tmp_path):
    job = _job(tmp_path)
    written = farm.write_flamenco_job(job, tmp_path / "jobs" / "a", worker_tag="gpu")
    body = json.loads((tmp_path / "jobs" / "a" / "flamenco_job.json").read_text())
    assert body["type"] == "hapticfluid-bake-render" == farm.FLAMENCO_JOB_TYPE.stem
    assert body["worker_tag"] == "gpu"
    s = body["settings"]
    assert (s["scene_file"], s["cache_dir"], s["output_dir"]) == ("shots/a.json", "cache/a", "renders/a")
    assert s["shared_root"] == tmp_path.as_posix() and s["frames"] == "1-48" and s["chunk_size"] == 10
    declared = set(re.findall(r'\{ key: "(\w+)"', farm.FLAMENCO_JOB_TYPE.read_text()))
    assert set(s) <= declared
    assert "/api/v3/jobs" in written["command"]


@pytest.mark.parametrize("field, what", [("cache_dir", "cache folder"), ("output_dir", "output folder"),
                                         ("scene_file", "scene file")])
def test_a_path_outside_the_shared_root_is_refused_naming_it(tmp_path, field, what):
    outside = tmp_path.parent / "elsewhere" / ("x.json" if field == "scene_file" else "x")
    job = _job(tmp_path / "root", **{field: str(outside)})
    with pytest.raises(ValueError, match=f"move the {what} under the shared root .*: '.*elsewhere.*' is not under it"):
        farm.write_openjd_job(job, tmp_path / "jobs")
    assert not (tmp_path / "jobs").exists()  # nothing written


def test_no_shared_root_or_a_bad_scene_is_refused(tmp_path):
    with pytest.raises(ValueError, match="set the shared root .*: it is empty"):
        farm.openjd_parameters(_job(tmp_path, shared_root=""))
    with pytest.raises(ValueError, match=r"must be a hapticfluid scene \.json or a \.blend"):
        farm.openjd_parameters(_job(tmp_path, scene_file=str(tmp_path / "a.txt")))
    with pytest.raises(ValueError, match="chunk size must be >= 1"):
        farm.openjd_parameters(_job(tmp_path, chunk_size=0))


def test_frames_and_chunks():
    assert farm.parse_frames("7") == [7]
    assert farm.parse_frames("1-4,9-13:2") == [1, 2, 3, 4, 9, 11, 13]
    assert farm.frame_chunks(3, 12, 4) == [(3, 6), (7, 10), (11, 12)]
    assert farm.frame_chunks(5, 5, 8) == [(5, 5)]
    for bad in ("4-1", "1-3,2", "a"):
        with pytest.raises(ValueError):
            farm.parse_frames(bad)
    with pytest.raises(ValueError, match="is empty"):
        farm.frame_chunks(5, 4, 2)


def test_the_bake_task_resumes_only_when_the_cache_has_a_checkpoint(tmp_path):
    cache = tmp_path / "c"
    assert "--resume" not in bake_step.bake_command_json(tmp_path / "s.json", 64, cache)
    checkpoint_path(cache).parent.mkdir(parents=True)
    checkpoint_path(cache).write_bytes(b"any")
    assert bake_step.bake_command_json(tmp_path / "s.json", 64, cache) == [
        "bake", str(tmp_path / "s.json"), "--resolution", "64", "--cache", str(cache), "--resume"]


def test_a_blend_scene_is_baked_by_the_add_ons_script_into_the_job_s_cache(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(ADDON))
    cmd = bake_step.bake_command_blend("blender", tmp_path / "shot.blend", 96, tmp_path / "c")
    assert cmd[:3] == ["blender", "--background", str(tmp_path / "shot.blend")]
    assert cmd[cmd.index("--python") + 1] == str(ADDON / "hapticfluid_blender" / "bake_blend.py")
    assert f"cache_dir = {str(tmp_path / 'c')!r}" in cmd[cmd.index("--python-expr") + 1]
    assert cmd[cmd.index("--") + 1:] == ["--resolution", "96"]


def test_the_bake_task_names_a_missing_scene(tmp_path, caplog):
    assert bake_step.run(str(tmp_path), "nope.json", 16, "c") == 2
    assert "scene file" in caplog.text and "does not exist" in caplog.text


def test_the_write_command_prints_the_submit_commands(tmp_path, capsys):
    from hapticfluid.farm.__main__ import main

    (tmp_path / "s.json").write_text("{}")
    assert main(["write", str(tmp_path / "s.json"), "--root", str(tmp_path), "--cache", str(tmp_path / "c"),
                 "--output", str(tmp_path / "o"), "--frames", "2-9", "--resolution", "32", "--job",
                 str(tmp_path / "job")]) == 0
    out = capsys.readouterr().out
    assert "openjd run" in out and "deadline bundle submit" in out and "/api/v3/jobs" in out
    assert main(["write", str(tmp_path / "s.json"), "--root", str(tmp_path / "o"), "--cache", str(tmp_path / "c"),
                 "--output", str(tmp_path / "o"), "--frames", "2-9", "--resolution", "32", "--job",
                 str(tmp_path / "job2")]) == 2
    assert "under the shared root" in capsys.readouterr().err


def test_a_render_chunk_of_frames_not_baked_is_an_error_naming_them():
    from hapticfluid.farm.chunks import check_frames, parse_args

    manifest = {"scene": {"frame_start": 1}, "last_frame": 4}
    check_frames([3, 4], manifest, "c")  # baked: no error
    with pytest.raises(SystemExit, match=r"frame\(s\) \[5, 6\] are not baked in c \(baked: 1..4\)"):
        check_frames([4, 5, 6], manifest, "c")
    with pytest.raises(SystemExit, match=r"baked: none"):
        check_frames([1], {"scene": {"frame_start": 1}, "last_frame": None}, "c")
    args = parse_args(["--root", "/r", "--size", "64", "48", "cache", "5-8", "out"])
    assert (args.root, tuple(args.size), args.cache, args.frames, args.outdir) == ("/r", (64, 48), "cache", "5-8", "out")
