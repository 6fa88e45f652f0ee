// Links WESL with the npm `wesl` linker (tests/node/package.json pins it), as a
// JavaScript host would: the kernels' modules are one library bundle, the package
// `bevy_airlight`; each job's root module imports from it.
//
//   node wesl-link.mjs <modules dir> <jobs.json>
//
// jobs.json: [{ "name": …, "main": <root module source> }, …]. Writes to stdout
// a JSON object { <name>: { "wgsl": … } | { "error": … } }.
import { link } from "wesl";
import { readFileSync, readdirSync } from "node:fs";

const [dir, jobsFile] = process.argv.slice(2);
const modules = {};
for (const f of readdirSync(dir).filter((f) => f.endsWith(".wesl")).sort()) {
  modules[`./${f}`] = readFileSync(`${dir}/${f}`, "utf8");
}
const lib = { name: "bevy_airlight", edition: "unstable_2025", modules };
const out = {};
for (const job of JSON.parse(readFileSync(jobsFile, "utf8"))) {
  try {
    const linked = await link({ weslSrc: { "./main.wesl": job.main }, rootModuleName: "main", libs: [lib] });
    out[job.name] = { wgsl: linked.dest };
  } catch (e) {
    out[job.name] = { error: String(e && e.message ? e.message : e) };
  }
}
process.stdout.write(JSON.stringify(out));
