// ---- shapes (tyndall::shapes) ----

fn intersect_sphere(p: Primitive, ray: Ray, t_max: f32) -> f32 {
    let center = p.a.xyz;
    let radius = p.a.w;
    let oc = ray.origin - center;
    let b = dot(oc, ray.direction);
    let c = dot(oc, oc) - radius * radius;
    let perp = oc - b * ray.direction;
    let disc = radius * radius - dot(perp, perp);
    if disc < 0.0 {
        return -1.0;
    }
    let sq = sqrt(disc);
    var q = -b + sq;
    if b > 0.0 {
        q = -b - sq;
    }
    let t0 = min(q, c / q);
    let t1 = max(q, c / q);
    if t0 > 0.0 && t0 < t_max {
        return t0;
    }
    if t1 > 0.0 && t1 < t_max {
        return t1;
    }
    return -1.0;
}

fn intersect_quad(p: Primitive, ray: Ray, t_max: f32) -> f32 {
    let normal = p.d.xyz;
    let denom = dot(normal, ray.direction);
    if denom == 0.0 || (p.one_sided != 0u && denom > 0.0) {
        return -1.0;
    }
    let t = dot(normal, p.a.xyz - ray.origin) / denom;
    if !(t > 0.0 && t < t_max) {
        return -1.0;
    }
    let q = ray_at(ray, t) - p.a.xyz;
    let u = dot(p.e.xyz, cross(q, p.c.xyz));
    let v = dot(p.e.xyz, cross(p.b.xyz, q));
    if u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0 {
        return t;
    }
    return -1.0;
}

fn intersect_triangle(p: Primitive, ray: Ray, t_max: f32) -> f32 {
    let e1 = p.b.xyz;
    let e2 = p.c.xyz;
    let pv = cross(ray.direction, e2);
    let det = dot(e1, pv);
    if det == 0.0 || (p.one_sided != 0u && det < 0.0) {
        return -1.0;
    }
    let inv = 1.0 / det;
    let s = ray.origin - p.a.xyz;
    let u = dot(s, pv) * inv;
    if u < 0.0 || u > 1.0 {
        return -1.0;
    }
    let q = cross(s, e1);
    let v = dot(ray.direction, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return -1.0;
    }
    let t = dot(e2, q) * inv;
    if t > 0.0 && t < t_max {
        return t;
    }
    return -1.0;
}

// Distance to primitive `i` along `ray` in (0, t_max), or −1.
fn intersect(i: u32, ray: Ray, t_max: f32) -> f32 {
    let p = primitives[i];
    if p.kind == SHAPE_SPHERE {
        return intersect_sphere(p, ray, t_max);
    }
    if p.kind == SHAPE_QUAD {
        return intersect_quad(p, ray, t_max);
    }
    return intersect_triangle(p, ray, t_max);
}

fn geometric_normal(i: u32, x: vec3<f32>) -> vec3<f32> {
    let p = primitives[i];
    if p.kind == SHAPE_SPHERE {
        return normalize(x - p.a.xyz);
    }
    return p.d.xyz;
}

struct Hit {
    t: f32,
    primitive: u32,
    found: bool,
}
