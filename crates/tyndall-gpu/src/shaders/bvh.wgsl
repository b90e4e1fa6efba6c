// ---- the BVH (bvh.rs) ----

// A walk of the threaded BVH along one ray: the next node to visit and
// the rest of the current leaf's primitives.
struct BvhWalk {
    origin: vec3<f32>,
    // 1/direction, with zero components replaced by a tiny value of
    // their sign, so that no slab test meets 0·∞.
    inverse: vec3<f32>,
    node: u32,
    primitive: u32,
    primitive_end: u32,
}

// Marks the end of a walk.
const NO_PRIMITIVE: u32 = 0xffffffffu;

fn bvh_walk(ray: Ray) -> BvhWalk {
    let tiny = select(vec3<f32>(1e-20), vec3<f32>(-1e-20), ray.direction < vec3<f32>(0.0));
    let d = select(ray.direction, tiny, abs(ray.direction) < vec3<f32>(1e-20));
    return BvhWalk(ray.origin, 1.0 / d, 0u, 0u, 0u);
}

// The next primitive whose leaf box the ray meets in [0, t_max], or
// NO_PRIMITIVE: a subtree whose box the ray misses is skipped whole.
// Callers test each primitive themselves and may lower t_max between
// calls (the nearest hit so far).
fn bvh_next(walk: ptr<function, BvhWalk>, t_max: f32) -> u32 {
    loop {
        if (*walk).primitive < (*walk).primitive_end {
            let p = (*walk).primitive;
            (*walk).primitive = p + 1u;
            return p;
        }
        if (*walk).node >= params.node_count {
            return NO_PRIMITIVE;
        }
        let node = bvh_nodes[(*walk).node];
        let a = (node.min - (*walk).origin) * (*walk).inverse;
        let b = (node.max - (*walk).origin) * (*walk).inverse;
        let lo = min(a, b);
        let hi = max(a, b);
        let near = max(max(lo.x, lo.y), max(lo.z, 0.0));
        let far = min(min(hi.x, hi.y), min(hi.z, t_max));
        if near <= far {
            if node.count > 0u {
                (*walk).primitive = node.first;
                (*walk).primitive_end = node.first + node.count;
            }
            (*walk).node += 1u;
        } else {
            (*walk).node = node.skip;
        }
    }
    return NO_PRIMITIVE;
}

// Primary visibility: the nearest hit, through the BVH.
fn nearest_hit(ray: Ray) -> Hit {
    var hit = Hit(INFINITE, 0u, false);
    var walk = bvh_walk(ray);
    loop {
        let i = bvh_next(&walk, hit.t);
        if i == NO_PRIMITIVE {
            break;
        }
        let t = intersect(i, ray, hit.t);
        if t > 0.0 {
            hit = Hit(t, i, true);
        }
    }
    return hit;
}
