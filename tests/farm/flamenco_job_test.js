// SPDX-License-Identifier: GPL-3.0-or-later
// The Flamenco job type run by node against flamenco_harness.js (Flamenco 3.5-3.7 job-compiler
// API): the task graph and commands for a job written by `python3 -m hapticfluid.farm write`,
// chunking of split frame ranges, and refusals. Usage: node flamenco_job_test.js JOB_TYPE.js PYTHON
"use strict";
const assert = require("assert");
const cp = require("child_process");
const fs = require("fs");
const os = require("os");
const path = require("path");
const { compile } = require("./flamenco_harness.js");

const [script, python] = process.argv.slice(2);
let checks = 0;
function check(name, fn) { fn(); checks++; console.log(`ok - ${name}`); }

// 1. The submission the Python writer makes, compiled.
const dir = fs.mkdtempSync(path.join(os.tmpdir(), "hf_flamenco_"));
const root = path.join(dir, "shared");
try {
    fs.mkdirSync(path.join(root, "scenes"), { recursive: true });
    fs.copyFileSync(path.join(__dirname, "tiny_scene.json"), path.join(root, "scenes", "s.json"));
    cp.execFileSync(python, ["-m", "hapticfluid.farm", "write", path.join(root, "scenes/s.json"), "--root", root,
        "--cache", path.join(root, "caches/s"), "--output", path.join(root, "renders/s"), "--frames", "3-12",
        "--resolution", "96", "--chunk-size", "4", "--job", path.join(root, "jobs/s")],
        { stdio: ["ignore", "ignore", "inherit"] });
    const jobDir = path.join(root, "jobs/s");
    const submission = JSON.parse(fs.readFileSync(path.join(jobDir, "flamenco_job.json"), "utf8"));
    check("the submission names this job type (the script's file name)", () => {
        assert.strictEqual(submission.type, path.basename(script, ".js"));
        assert.strictEqual(fs.readFileSync(path.join(jobDir, path.basename(script)), "utf8"), fs.readFileSync(script, "utf8"));
    });
    const { tasks } = compile(script, submission);
    check("one bake task of the GPU task type, then render chunks 3-6, 7-10, 11-12", () => {
        assert.deepStrictEqual(tasks.map(t => [t.name, t.type]),
            [["bake", "hapticfluid-gpu"], ["render-3-6", "blender"], ["render-7-10", "blender"], ["render-11-12", "blender"]]);
    });
    check("the bake depends on nothing, every render chunk on the bake alone", () => {
        assert.deepStrictEqual(tasks.map(t => t.dependsOn), [[], ["bake"], ["bake"], ["bake"]]);
    });
    check("the bake command: hapticfluid.farm bake with the relative paths and the shared root", () => {
        assert.strictEqual(tasks[0].commands.length, 1);
        const c = tasks[0].commands[0];
        assert.strictEqual(c.type, "exec");
        assert.strictEqual(c.parameters.exe, "env");
        assert.deepStrictEqual(c.parameters.args, ["PYTHONPATH=", "/usr/bin/python3", "-m", "hapticfluid.farm", "bake",
            "--root", root, "--resolution", "96", "--cache", "caches/s", "--blender", "{blender}", "scenes/s.json"]);
    });
    check("each render command renders its chunk of the cache into the output folder with Blender", () => {
        for (const [i, chunk] of [[1, "3-6"], [2, "7-10"], [3, "11-12"]]) {
            const a = tasks[i].commands[0].parameters.args;
            assert.strictEqual(a[1], "{blender}");
            assert.deepStrictEqual(a.slice(a.indexOf("--") + 1),
                ["--root", root, "--samples", "16", "--size", "320", "240", "caches/s", chunk, "renders/s"]);
            assert.ok(a.includes("--background") && a.includes("import hapticfluid_blender as a; a.render_main()"));
        }
    });
} finally {
    fs.rmSync(dir, { recursive: true, force: true });
}

// 2. A split frame list, chunks of 2, settings from a farm's own submission.
const base = { shared_root: "/mnt/farm", scene_file: "a.blend", cache_dir: "c", output_dir: "o", resolution: 64 };
check("frames 1-3,10-12 in chunks of 2: 1-2, 3-3, 10-11, 12-12", () => {
    const { tasks } = compile(script, { settings: { ...base, frames: "1-3,10-12", chunk_size: 2, python_path: "/opt/hf" } });
    assert.deepStrictEqual(tasks.map(t => t.name), ["bake", "render-1-2", "render-3-3", "render-10-11", "render-12-12"]);
    assert.strictEqual(tasks[0].commands[0].parameters.args[0], "PYTHONPATH=/opt/hf");
});

// 3. A chained bake: bake_chunk_size 4 over frames 3-12 (as `write --bake-chunk 4` submits it).
check("bake_chunk_size 4 over 3-12: bake chunks 3-6, 7-10, 11-12 chained, each chunk's renders after it alone", () => {
    const { tasks } = compile(script, { settings: { ...base, frames: "3-12", chunk_size: 3, bake_chunk_size: 4 } });
    assert.deepStrictEqual(tasks.map(t => [t.name, t.type, t.dependsOn]), [
        ["bake-3-6", "hapticfluid-gpu", []],
        ["render-3-5", "blender", ["bake-3-6"]], ["render-6-6", "blender", ["bake-3-6"]],
        ["bake-7-10", "hapticfluid-gpu", ["bake-3-6"]],
        ["render-7-9", "blender", ["bake-7-10"]], ["render-10-10", "blender", ["bake-7-10"]],
        ["bake-11-12", "hapticfluid-gpu", ["bake-7-10"]],
        ["render-11-12", "blender", ["bake-11-12"]]]);
    const bakeArgs = tasks.filter(t => t.type === "hapticfluid-gpu").map(t => t.commands[0].parameters.args);
    assert.deepStrictEqual(bakeArgs.map(a => a.slice(a.indexOf("a.blend"))),
                           [["a.blend", "--until", "6"], ["a.blend", "--until", "10"], ["a.blend", "--until", "12"]]);
});
check("a chained bake over split frames 1-3,10-12: every chunk baked in turn, renders only of frames asked for", () => {
    const { tasks } = compile(script, { settings: { ...base, frames: "1-3,10-12", chunk_size: 8, bake_chunk_size: 5 } });
    assert.deepStrictEqual(tasks.map(t => [t.name, t.dependsOn]), [
        ["bake-1-5", []], ["render-1-3", ["bake-1-5"]], ["bake-6-10", ["bake-1-5"]], ["render-10-10", ["bake-6-10"]],
        ["bake-11-12", ["bake-6-10"]], ["render-11-12", ["bake-11-12"]]]);
});
check("bake_chunk_size 0 or covering every frame: one bake task without --until", () => {
    for (const size of [0, 10, 99]) {
        const { tasks } = compile(script, { settings: { ...base, frames: "3-12", bake_chunk_size: size } });
        assert.deepStrictEqual(tasks.filter(t => t.type === "hapticfluid-gpu").map(t => t.name), ["bake"]);
        assert.ok(!tasks[0].commands[0].parameters.args.includes("--until"));
    }
});
check("a negative bake_chunk_size is refused naming the setting", () => {
    assert.throws(() => compile(script, { settings: { ...base, frames: "1-4", bake_chunk_size: -2 } }),
                  /bake_chunk_size must be 0 \(one bake task\) or a number of frames >= 1, got -2/);
});

// 4. Refusals: a backwards range, a missing required setting, an undeclared one.
check("a backwards frame range is refused", () => {
    assert.throws(() => compile(script, { settings: { ...base, frames: "9-2" } }), /ends before it starts/);
});
check("a missing required setting is refused", () => {
    const { cache_dir, ...rest } = base;
    assert.throws(() => compile(script, { settings: { ...rest, frames: "1-4" } }), /required setting "cache_dir"/);
});
check("an undeclared setting is refused", () => {
    assert.throws(() => compile(script, { settings: { ...base, frames: "1-4", gpu: true } }), /not declared/);
});
console.log(`flamenco job type: ${checks} checks passed`);
