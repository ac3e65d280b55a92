# SPDX-License-Identifier: GPL-3.0-or-later
"""hapticfluid.farm: the job writer (paths relative to the shared root, names the job files
declare), frame chunks, the chained bake's OpenJD template, the bake task's command lines and the
shipped job files."""

import json
import re
import sys
from pathlib import Path

import pytest
import yaml

from hapticfluid import farm
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
    assert s["bake_chunk_size"] == 0
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


def test_the_bake_task_always_resumes_the_lazy_cache_and_stops_at_until(tmp_path):
    # --resume on an empty cache bakes from the first frame, so every run and re-queue is one command
    assert bake_step.bake_command_json(tmp_path / "s.json", 64, tmp_path / "c") == [
        "bake", str(tmp_path / "s.json"), "--resolution", "64", "--cache", str(tmp_path / "c"), "--resume"]
    assert bake_step.bake_command_json(tmp_path / "s.json", 64, tmp_path / "c", until=24)[-3:] == [
        "--resume", "--until", "24"]


def test_the_bake_task_passes_until_to_the_bake(tmp_path, monkeypatch):
    import hapticfluid.cli

    seen = []
    monkeypatch.setattr(hapticfluid.cli, "main", lambda argv: seen.append(argv) or 0)
    (tmp_path / "shots").mkdir()
    (tmp_path / "shots" / "a.json").write_text("{}")
    from hapticfluid.farm.__main__ import main

    assert main(["bake", "--root", str(tmp_path), "--resolution", "16", "--cache", "c", "shots/a.json",
                 "--until", "24"]) == 0
    assert seen == [["bake", str(tmp_path / "shots" / "a.json"), "--resolution", "16", "--cache",
                     str(tmp_path / "c"), "--resume", "--until", "24"]]


def test_the_bake_command_line_takes_until_and_refuses_a_bad_one(capsys):
    from hapticfluid.farm.__main__ import build_parser

    args = build_parser().parse_args(["bake", "s.json", "--resolution", "16", "--cache", "c", "--until", "24"])
    assert args.until == 24
    assert build_parser().parse_args(["bake", "s.json", "--resolution", "16", "--cache", "c"]).until is None
    with pytest.raises(SystemExit):
        build_parser().parse_args(["bake", "s.json", "--resolution", "16", "--cache", "c", "--until", "x"])
    assert "--until: must be a frame number (an integer), got 'x'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        build_parser().parse_args(["write", "s.json", "--root", "r", "--cache", "c", "--output", "o", "--frames",
                                   "1-4", "--resolution", "16", "--job", "j", "--bake-chunk", "-1"])
    assert "--bake-chunk: must be 0 (one bake task) or a number of frames >= 1, got -1" in capsys.readouterr().err


def _steps(template_text):
    return {s["name"]: s for s in yaml.safe_load(template_text)["steps"]}


def test_bake_chunks_split_the_frames_or_keep_one_task():
    assert farm.bake_chunks(1, 48, 0) == [(1, 48)]
    assert farm.bake_chunks(1, 48, 48) == farm.bake_chunks(1, 48, 100) == [(1, 48)]
    assert farm.bake_chunks(1, 50, 24) == [(1, 24), (25, 48), (49, 50)]
    with pytest.raises(ValueError, match=r"bake chunk size must be 0 \(one bake task\) or a number of frames >= 1, got -3"):
        farm.bake_chunks(1, 48, -3)


def test_a_chained_bake_is_one_bake_and_one_render_step_per_chunk(tmp_path):
    job = _job(tmp_path, frame_end=50, bake_chunk_size=24, chunk_size=5)
    farm.write_openjd_job(job, tmp_path / "jobs" / "a")
    text = (tmp_path / "jobs" / "a" / "template.yaml").read_text()
    t = yaml.safe_load(text)
    assert [s["name"] for s in t["steps"]] == ["Bake 1-24", "Render 1-24", "Bake 25-48", "Render 25-48",
                                               "Bake 49-50", "Render 49-50"]
    steps = _steps(text)
    shipped = _template()
    # each bake chunk depends on the chunk before it only; each render step on its own chunk's bake only
    assert "dependencies" not in steps["Bake 1-24"]
    assert steps["Bake 25-48"]["dependencies"] == [{"dependsOn": "Bake 1-24"}]
    assert steps["Bake 49-50"]["dependencies"] == [{"dependsOn": "Bake 25-48"}]
    for chunk in ("1-24", "25-48", "49-50"):
        render = steps[f"Render {chunk}"]
        assert render["dependencies"] == [{"dependsOn": f"Bake {chunk}"}]
        (param,) = render["parameterSpace"]["taskParameterDefinitions"]
        assert param["range"] == chunk and param["type"] == "CHUNK[INT]"
        assert render["script"] == shipped["steps"][1]["script"]  # the shipped command, unchanged
        bake = steps[f"Bake {chunk}"]
        assert bake["hostRequirements"] == shipped["steps"][0]["hostRequirements"]
        args = bake["script"]["actions"]["onRun"]["args"]
        assert args == shipped["steps"][0]["script"]["actions"]["onRun"]["args"] + ["--until", chunk.split("-")[1]]
    # the steps fix the frames: no Frames parameter, and none in the values
    assert "Frames" not in {p["name"] for p in t["parameterDefinitions"]}
    assert {p["name"] for p in t["parameterDefinitions"]} == {p["name"] for p in shipped["parameterDefinitions"]} - {"Frames"}
    values = json.loads((tmp_path / "jobs" / "a" / "parameters.json").read_text())
    assert "Frames" not in values and values["ChunkSize"] == 5
    assert t["jobEnvironments"] == shipped["jobEnvironments"]


def test_one_bake_task_writes_the_shipped_template_unchanged(tmp_path):
    for size in (0, 48, 60):
        farm.write_openjd_job(_job(tmp_path, bake_chunk_size=size), tmp_path / f"j{size}")
        assert (tmp_path / f"j{size}" / "template.yaml").read_text() == farm.OPENJD_TEMPLATE.read_text()
        assert json.loads((tmp_path / f"j{size}" / "parameters.json").read_text())["Frames"] == "1-48"


def test_the_chained_template_refuses_a_shipped_template_of_another_shape():
    text = farm.OPENJD_TEMPLATE.read_text()
    with pytest.raises(RuntimeError, match=r"exactly one 'range: \"\{\{Param.Frames\}\}\"' in the Render step"):
        farm.chained_openjd_template(text.replace('range: "{{Param.Frames}}"', 'range: "1-9"'), [(1, 4), (5, 9)], "1-9")
    with pytest.raises(RuntimeError, match="must have the steps Bake, then Render"):
        farm.chained_openjd_template(text.replace("  - name: Render\n", "  - name: Draw\n"), [(1, 4), (5, 9)], "1-9")
    with pytest.raises(ValueError, match="at least 2 chunks"):
        farm.chained_openjd_template(text, [(1, 9)], "1-9")


def test_a_blend_scene_is_baked_by_the_add_ons_entry_point_into_the_job_s_cache(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(ADDON))
    cmd = bake_step.bake_command_blend("blender", tmp_path / "shot.blend", 96, tmp_path / "c")
    assert cmd[:3] == ["blender", "--background", str(tmp_path / "shot.blend")]
    assert "--python" not in cmd  # no file of the add-on is named
    assert cmd[cmd.index("--python-expr") + 1] == f"import sys; sys.path.insert(0, {str(ADDON)!r}); " \
                                                  f"{farm.BLENDER_BAKE_EXPR}"
    assert cmd[cmd.index("--") + 1:] == ["--resolution", "96", "--cache", str(tmp_path / "c"), "--resume"]
    cmd = bake_step.bake_command_blend("blender", tmp_path / "shot.blend", 96, tmp_path / "c", until=12)
    assert cmd[cmd.index("--") + 1:] == ["--resolution", "96", "--cache", str(tmp_path / "c"), "--resume",
                                         "--until", "12"]


def test_the_job_files_render_through_the_add_ons_entry_point():
    """The shipped OpenJD template and Flamenco job type call the add-on's render_main, as the
    package's own constant says, and name none of the add-on's modules."""
    for path in (farm.OPENJD_TEMPLATE, farm.FLAMENCO_JOB_TYPE):
        text = path.read_text()
        assert text.count(farm.BLENDER_RENDER_EXPR) == 1, path.name
        assert not re.search(r"hapticfluid_blender\.\w", text), path.name


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
