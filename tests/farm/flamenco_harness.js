// SPDX-License-Identifier: GPL-3.0-or-later
// A small stand-in for Flamenco Manager's job compiler runtime, for tests: it implements the
// job-compiler API documented for Flamenco 3.5-3.7 (flamenco.blender.org/usage/job-types/) that a
// job type script calls - the globals author.Task(name, type) and author.Command(type, params),
// task.addCommand(cmd), task.addDependency(task), job.addTask(task), job.settings - and what the
// Manager does around it: load the script, read JOB_TYPE, fill in setting defaults, refuse a
// submission missing a required setting or carrying one the job type does not declare, then call
// compileJob(job). It records the task graph as plain objects.
"use strict";
const fs = require("fs");
const vm = require("vm");

function makeAuthor() {
    return {
        Task(name, type) {
            if (typeof name !== "string" || typeof type !== "string") throw new TypeError("author.Task(name, type)");
            return {
                name, type, commands: [], dependencies: [],
                addCommand(cmd) { this.commands.push(cmd); },
                addDependency(task) {
                    if (!task || typeof task.name !== "string") throw new TypeError("addDependency(task)");
                    this.dependencies.push(task);
                },
            };
        },
        Command(type, parameters) {
            if (typeof type !== "string" || typeof parameters !== "object") throw new TypeError("author.Command(type, params)");
            return { type, parameters };
        },
    };
}

function loadJobType(scriptPath) {
    const context = vm.createContext({ author: makeAuthor(), print: (...a) => console.log(...a) });
    // `const JOB_TYPE` stays in the script's scope: hand it out the way the Manager reads it.
    vm.runInContext(fs.readFileSync(scriptPath, "utf8") + "\n;globalThis.__jobType = JOB_TYPE;", context,
                    { filename: scriptPath });
    return context;
}

function checkSettings(jobType, given) {
    const settings = {};
    const declared = new Map(jobType.settings.map(s => [s.key, s]));
    for (const key of Object.keys(given)) {
        if (!declared.has(key)) throw new Error(`setting "${key}" is not declared by job type "${jobType.label}"`);
    }
    for (const spec of jobType.settings) {
        const value = key => (key in given ? given[key] : spec.default);
        const v = value(spec.key);
        if (v === undefined) {
            if (spec.required) throw new Error(`required setting "${spec.key}" is missing`);
            continue;
        }
        if (spec.type === "int32" && !Number.isInteger(v)) throw new Error(`setting "${spec.key}" must be int32, got ${v}`);
        if (spec.type === "string" && typeof v !== "string") throw new Error(`setting "${spec.key}" must be a string`);
        settings[spec.key] = v;
    }
    return settings;
}

// Compile a job of the script's type; returns {jobType, tasks: [{name, type, commands, dependsOn}]}.
function compile(scriptPath, submission) {
    const context = loadJobType(scriptPath);
    const jobType = context.__jobType;
    const tasks = [];
    const job = {
        name: submission.name || "test job",
        priority: submission.priority || 50,
        settings: checkSettings(jobType, submission.settings || {}),
        metadata: submission.metadata || {},
        addTask(task) { tasks.push(task); },
    };
    context.__job = job;
    vm.runInContext("compileJob(__job);", context);
    const names = new Set(tasks.map(t => t.name));
    for (const t of tasks) {
        for (const d of t.dependencies) {
            if (!names.has(d.name)) throw new Error(`task "${t.name}" depends on "${d.name}", which the job lacks`);
        }
    }
    return {
        jobType,
        // JSON round trip: plain objects of this realm (the script built them in the vm context)
        tasks: tasks.map(t => ({ name: t.name, type: t.type, commands: JSON.parse(JSON.stringify(t.commands)),
                                 dependsOn: t.dependencies.map(d => d.name) })),
    };
}

module.exports = { compile };
