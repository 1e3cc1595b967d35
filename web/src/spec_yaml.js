// The spec editor's files as the command line reads them: spec.yaml (faces by id, each
// face's name beside it as a comment) and points.csv (x, y, z, nx, ny, nz in mm, part frame).

// The sections in the order a spec is written; a spec has no others (the reader refuses them).
const ORDER = ['scanner', 'part', 'gdt', 'roles', 'markers', 'fixtures', 'registration', 'cell', 'planner', 'tasks'];

// A list of face ids, written one per line with the face's name when it has one.
class FaceList {
  constructor(ids, faces) {
    this.ids = [...ids].sort((a, b) => a - b);
    this.names = this.ids.map((id) => faces[id - 1]?.name || '');
  }
}

const RESERVED = /^(true|false|yes|no|on|off|y|n|null|~)$/i;
function scalar(value) {
  if (value === null || value === undefined) return 'null';
  if (typeof value === 'number' || typeof value === 'boolean') return String(value);
  const s = String(value);
  return /^[A-Za-z_/.][\w./ -]*$/.test(s) && !RESERVED.test(s) && !s.endsWith(' ') ? s : JSON.stringify(s);
}
const isScalar = (v) => v === null || typeof v !== 'object';

// YAML lines for `value` under `key` at `indent` (a list item's first key shares its dash).
function emit(key, value, indent, lines) {
  const pad = ' '.repeat(indent), head = `${pad}${key}:`;
  if (value instanceof FaceList) {
    if (value.names.every((n) => !n)) {
      lines.push(`${head} [${value.ids.join(', ')}]`);
    } else {
      lines.push(head);
      value.ids.forEach((id, i) => lines.push(`${pad}  - ${id}${value.names[i] ? `  # ${value.names[i]}` : ''}`));
    }
  } else if (Array.isArray(value)) {
    if (value.every(isScalar)) {
      lines.push(`${head} [${value.map(scalar).join(', ')}]`);
      return;
    }
    lines.push(head);
    for (const item of value) emitItem(item, indent + 2, lines);
  } else if (value && typeof value === 'object') {
    lines.push(head);
    for (const [k, v] of Object.entries(value)) emit(k, v, indent + 2, lines);
  } else {
    lines.push(`${head} ${scalar(value)}`);
  }
}
function emitItem(item, indent, lines) {
  const pad = ' '.repeat(indent);
  if (Array.isArray(item) && item.every(isScalar)) {
    lines.push(`${pad}- [${item.map(scalar).join(', ')}]`);
  } else if (item && typeof item === 'object' && !Array.isArray(item)) {
    const inner = [];
    for (const [k, v] of Object.entries(item)) emit(k, v, indent + 2, inner);
    if (inner.length) inner[0] = `${pad}- ${inner[0].slice(indent + 2)}`;
    lines.push(...inner);
  } else if (Array.isArray(item)) {
    lines.push(`${pad}-`);
    for (const sub of item) emitItem(sub, indent + 2, lines);
  } else {
    lines.push(`${pad}- ${scalar(item)}`);
  }
}

// The spec of the editor's `state` (its document with the tasks and roles written in).
export function specYaml(state, data) {
  const spec = structuredClone(state.document);
  delete spec.tasks;
  delete spec.roles;
  const roles = {};
  for (const [role, ids] of Object.entries(state.roles)) if (ids.size) roles[role] = new FaceList(ids, data.faces);
  if (Object.keys(roles).length) spec.roles = roles;
  if (state.tasks.length) {
    spec.tasks = state.tasks.map((t) => {
      if (t.type === 'points') return { type: 'points', file: 'points.csv' };
      return t.faces.size ? { type: t.type, faces: new FaceList(t.faces, data.faces) } : { type: t.type };
    });
  }
  const lines = [`# Inspection spec for ${data.title}, written by the scanplan spec editor (scanplan ${data.header.version}).`];
  if (state.tasks.some((t) => t.type === 'points')) lines.push('# The control points are in points.csv beside it.');
  const keys = [...ORDER.filter((k) => k in spec), ...Object.keys(spec).filter((k) => !ORDER.includes(k))];
  for (const key of keys) emit(key, spec[key], 0, lines);
  return `${lines.join('\n')}\n`;
}

export function pointsCsv(points) {
  const rows = points.map((p) => [...p.position.map((x) => x.toFixed(6)), ...p.normal.map((x) => x.toFixed(9))].join(','));
  return `x,y,z,nx,ny,nz\n${rows.join('\n')}\n`;
}
