// A point near a face snapped onto the face's exact elementary surface (as the spec editor's
// data gives it: plane, cylinder, cone, sphere or torus, mm, part frame), with the surface's
// normal there, turned to the side of `near` (the mesh's outward normal at the click).
// Returns null for other surfaces, and where the projection is undefined (on an axis).

const add = (a, b) => a.map((x, i) => x + b[i]);
const sub = (a, b) => a.map((x, i) => x - b[i]);
const scale = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const norm = (a) => Math.sqrt(dot(a, a));

// The part of `v` across the unit `axis`, and along it.
function split(v, axis) {
  const along = dot(v, axis);
  return [sub(v, scale(axis, along)), along];
}

function project(surface, p) {
  const o = surface.origin, v = sub(p, o);
  switch (surface.type) {
    case 'plane': {
      const n = surface.axis;
      return { position: sub(p, scale(n, dot(v, n))), normal: n };
    }
    case 'cylinder': {
      const [radial, h] = split(v, surface.axis), r = norm(radial);
      if (r === 0) return null;
      const u = scale(radial, 1 / r);
      return { position: add(add(o, scale(surface.axis, h)), scale(u, surface.radius)), normal: u };
    }
    case 'cone': {  // radius R + h tan(a) at height h: the generatrix through p's half-plane
      const [radial, h] = split(v, surface.axis), r = norm(radial);
      if (r === 0) return null;
      const u = scale(radial, 1 / r), a = surface.semi_angle;
      const t = h * Math.cos(a) + (r - surface.radius) * Math.sin(a);
      const position = add(add(o, scale(surface.axis, t * Math.cos(a))), scale(u, surface.radius + t * Math.sin(a)));
      return { position, normal: add(scale(surface.axis, -Math.sin(a)), scale(u, Math.cos(a))) };
    }
    case 'sphere': {
      const r = norm(v);
      if (r === 0) return null;
      const u = scale(v, 1 / r);
      return { position: add(o, scale(u, surface.radius)), normal: u };
    }
    case 'torus': {
      const [radial] = split(v, surface.axis), r = norm(radial);
      if (r === 0) return null;
      const ring = add(o, scale(radial, surface.radius / r)), w = sub(p, ring), d = norm(w);
      if (d === 0) return null;
      const u = scale(w, 1 / d);
      return { position: add(ring, scale(u, surface.minor_radius)), normal: u };
    }
    default:
      return null;
  }
}

export function snapToSurface(surface, point, near) {
  if (!surface) return null;
  const snapped = project(surface, point);
  if (!snapped) return null;
  if (dot(snapped.normal, near) < 0) snapped.normal = scale(snapped.normal, -1);
  return snapped;
}
