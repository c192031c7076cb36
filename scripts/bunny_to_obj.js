#!/usr/bin/env node
// scripts/bunny_to_obj.js — converts the Stanford bunny of the npm package `bunny` (public domain; positions and
// cells) into scenes/bunny.obj, once. If the scan has holes, every boundary loop is closed with a
// fan around the loop's centroid so that the mesh is closed (World3 integrates mass properties over the volume),
// and the triangles are flipped if needed so that they are counter-clockwise seen from outside.
//
// Usage: cd /tmp && npm pack bunny && tar xzf bunny-1.0.1.tgz   (unpacks to /tmp/package)
//        node scripts/bunny_to_obj.js /tmp/package/index.js scenes/bunny.obj
'use strict';
const fs = require('fs');
const [src, dst] = process.argv.slice(2);
if (!src || !dst) {
  console.error('usage: bunny_to_obj.js path/to/bunny/index.js out.obj');
  process.exit(2);
}
const bunny = require(require('path').resolve(src));
const pos = bunny.positions.map((p) => p.slice());
let cells = bunny.cells.map((c) => c.slice());

// Directed edges: a boundary edge (a -> b) has no partner (b -> a).
function directedEdges(tris) {
  const m = new Map();
  for (const [a, b, c] of tris) for (const [u, v] of [[a, b], [b, c], [c, a]]) m.set(u + ',' + v, (m.get(u + ',' + v) || 0) + 1);
  return m;
}
let edges = directedEdges(cells);
for (const [k, n] of edges) if (n > 1) throw new Error('non-manifold or inconsistently oriented edge ' + k);
// Boundary loops follow the reversed boundary edges (the hole's fan must use each edge in the opposite direction).
const next = new Map();
for (const k of edges.keys()) {
  const [u, v] = k.split(',').map(Number);
  if (!edges.has(v + ',' + u)) next.set(v, u);
}
let holes = 0;
const seen = new Set();
for (const start of [...next.keys()].sort((a, b) => a - b)) {
  if (seen.has(start)) continue;
  const loop = [];
  for (let v = start; !seen.has(v); v = next.get(v)) {
    seen.add(v);
    loop.push(v);
  }
  const c = [0, 0, 0];
  for (const v of loop) for (let i = 0; i < 3; ++i) c[i] += pos[v][i] / loop.length;
  const ci = pos.length;
  pos.push(c);
  for (let i = 0; i < loop.length; ++i) cells.push([loop[i], loop[(i + 1) % loop.length], ci]);
  ++holes;
}
edges = directedEdges(cells);
for (const [k, n] of edges) {
  const [u, v] = k.split(',');
  if (n !== 1 || !edges.has(v + ',' + u)) throw new Error('mesh still open at edge ' + k);
}
// Signed volume: flip every triangle if the surface is inside out.
let vol = 0;
for (const [a, b, c] of cells) {
  const [p, q, r] = [pos[a], pos[b], pos[c]];
  vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) + p[2] * (q[0] * r[1] - q[1] * r[0])) / 6;
}
if (vol < 0) cells = cells.map(([a, b, c]) => [a, c, b]);
const lines = ['# Stanford bunny (public domain scan, Stanford Computer Graphics Laboratory), from the npm package',
  '# `bunny` 1.0.1; ' + holes + ' holes closed with fans by scripts/bunny_to_obj.js. Units as in the package.'];
for (const p of pos) lines.push('v ' + p.map((x) => +x.toFixed(6)).join(' '));
for (const t of cells) lines.push('f ' + t.map((i) => i + 1).join(' '));
fs.writeFileSync(dst, lines.join('\n') + '\n');
console.log(`${pos.length} vertices, ${cells.length} triangles, ${holes} holes closed, volume ${Math.abs(vol).toFixed(3)}`);
