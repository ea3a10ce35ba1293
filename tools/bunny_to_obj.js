#!/usr/bin/env node
// Convert the npm package `bunny` (positions + cells of the Stanford bunny) into a compact
// Wavefront OBJ: `v x y z` lines with 5 significant digits, then `f a b c` lines (1-based).
// No texture coordinates or normals: bumpsim's `Obj(..., atlas: true)` generates both.
//
// Usage (see docs/assets.md):
//   npm pack bunny@1.0.1 && tar xzf bunny-1.0.1.tgz
//   node tools/bunny_to_obj.js package > configs/assets/bunny.obj
"use strict";
const path = require("path");
const dir = path.resolve(process.argv[2] || "package");
const pkg = require(path.join(dir, "package.json"));
const { positions, cells } = require(dir);

// Keep only vertices some cell uses, in first-use order of the original numbering.
const used = new Array(positions.length).fill(false);
for (const c of cells) for (const k of c) used[k] = true;
const remap = new Array(positions.length).fill(-1);
let next = 0;
for (let k = 0; k < positions.length; k++) if (used[k]) remap[k] = next++;

const fmt = (x) => {
  const s = String(Number(x.toPrecision(5)));
  return s === "-0" ? "0" : s;
};
const out = [];
out.push(`# Stanford bunny from the npm package ${pkg.name}@${pkg.version} (${pkg.license}),`);
out.push("# originally from the Stanford 3D Scanning Repository. See docs/assets.md.");
out.push(`# ${next} vertices, ${cells.length} triangles; produced by tools/bunny_to_obj.js`);
out.push("o bunny");
for (let k = 0; k < positions.length; k++) {
  if (used[k]) out.push("v " + positions[k].map(fmt).join(" "));
}
for (const c of cells) {
  if (c.length !== 3) throw new Error(`expected triangles, found a cell of ${c.length}`);
  out.push("f " + c.map((k) => remap[k] + 1).join(" "));
}
process.stdout.write(out.join("\n") + "\n");
