// The spec editor's writer (web/src/spec_yaml.js) without a browser: a spec of every kind
// of value, on a cube whose faces have names (OBJ groups), read back by `scanplan sample`
// and by PyYAML against the document it was made from.
//
//   node web/test/spec_yaml_test.mjs SCANPLAN OUTDIR
//
// Exits 0 when every check passes, 1 otherwise, printing each check.

import { execFileSync } from 'node:child_process';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pointsCsv, specYaml } from '../src/spec_yaml.js';

const [scanplan, out] = process.argv.slice(2);
const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};

// A 100 mm cube, a named group per side ("side: -x" needs quoting in YAML).
const names = ['bottom', 'top', 'side: -x', 'yes', 'front', 'back'];
const corners = [[0, 0, 0], [100, 0, 0], [100, 100, 0], [0, 100, 0], [0, 0, 100], [100, 0, 100], [100, 100, 100], [0, 100, 100]];
const sides = [[1, 4, 3, 2], [5, 6, 7, 8], [1, 5, 8, 4], [2, 3, 7, 6], [1, 2, 6, 5], [4, 8, 7, 3]];
writeFileSync(join(out, 'cube.obj'), [...corners.map((c) => `v ${c.join(' ')}`),
  ...sides.flatMap((s, k) => [`g ${names[k]}`, `f ${s[0]} ${s[1]} ${s[2]}`, `f ${s[0]} ${s[2]} ${s[3]}`])].join('\n') + '\n');
// Its faces as the editor's page carries them.
execFileSync(scanplan, ['spec', '-q', join(out, 'cube.obj'), '-o', join(out, 'editor.html')]);
const page = readFileSync(join(out, 'editor.html'), 'utf8');
const open = '<script type="application/json" id="scanplan-data">';
const begin = page.indexOf(open) + open.length;
const { faces } = JSON.parse(page.slice(begin, page.indexOf('</script>', begin)).replaceAll('<\\/', '</'));
check(faces.length === 6 && faces.every((f) => f.name), `the cube has 6 named faces: ${faces.map((f) => f.name).join(', ')}`);

const idOf = (name) => faces.find((f) => f.name === name).id;
const state = {
  document: {
    scanner: 'laser-line',
    part: { rest: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]] },
    registration: { method: 'geometry', tolerance: 0.05 },
    planner: { seed: 3, tilt: [20, 40], lift_capability: false },
  },
  tasks: [{ type: 'surface', faces: new Set([idOf('top'), idOf('side: -x')]) }, { type: 'global', faces: new Set() },
    { type: 'points', faces: new Set() }],
  roles: { priority: new Set([idOf('yes')]), fixture: new Set([idOf('bottom')]), specular: new Set() },
  points: [{ position: [50, 50, 100], normal: [0, 0, 1] }],
};
const text = specYaml(state, { title: 'cube.obj', header: { version: 'test' }, faces });
writeFileSync(join(out, 'spec.yaml'), text);
writeFileSync(join(out, 'points.csv'), pointsCsv(state.points));
check(text.includes(`  - ${idOf('side: -x')}  # side: -x`) && text.includes(`  - ${idOf('yes')}  # yes`),
  'each face is written by id with its name beside it');

// scanplan reads it: the surface task on the two faces, the point on the top.
execFileSync(scanplan, ['sample', '-q', join(out, 'cube.obj'), '--spec', join(out, 'spec.yaml'), '-o', join(out, 's.json')]);
const sampled = JSON.parse(readFileSync(join(out, 's.json'), 'utf8'));
const samples = sampled.samples || sampled;
const surfaceFaces = new Set(samples.filter((s) => s.task === 'surface').map((s) => s.face));
check(surfaceFaces.size === 2 && surfaceFaces.has(idOf('top')) && surfaceFaces.has(idOf('side: -x')),
  `scanplan reads the spec: its surface task is on faces ${[...surfaceFaces].join(', ')}`);
check(samples.filter((s) => s.task === 'points').length === 1, 'and its control point');

// The document reads back as it was given, the faces as sorted ids.
const expected = {
  ...state.document,
  roles: { priority: [idOf('yes')], fixture: [idOf('bottom')] },
  tasks: [{ type: 'surface', faces: [idOf('top'), idOf('side: -x')].sort((a, b) => a - b) }, { type: 'global' },
    { type: 'points', file: 'points.csv' }],
};
const same = execFileSync('python3', ['-c', 'import json, sys, yaml; print(yaml.safe_load(open(sys.argv[1])) == json.loads(sys.argv[2]))',
  join(out, 'spec.yaml'), JSON.stringify(expected)], { encoding: 'utf8' });
check(same.trim() === 'True', 'PyYAML reads the document as it was given, the faces as sorted ids');
process.exit(failures.length === 0 ? 0 : 1);
