//! The checks of [`SceneDesc::validate`]: every value of every item in its
//! physical range, references between items, counts, and media that can
//! be tracked — one place for every loader and for descriptions made in
//! code.
//!
//! Errors name the field by the key the native format gives it
//! (docs/scene-format.md), so that a loader that keeps its text can point
//! at that key.

use super::{DescError, LightDesc, MediumDesc, Origin, RegionDesc, SceneDesc, ShapeDesc};
use crate::camera::{Aperture, FieldOfView};
use crate::color::Rgb;
use crate::limits;
use crate::materials::{Material, Surface};
use crate::media::Fog;
use crate::media::emission::{BlackbodyLaw, Emission};
use crate::media::tracking::MAX_VOLUMES;
use crate::media::volume::Density;
use crate::phase::PhaseFunction;
use crate::shapes::{Bounds, Shape};
use glam::Vec3;

mod light_groups;
mod mesh_attributes;

/// Largest |g| of a Henyey–Greenstein phase function.
const MAX_ASYMMETRY: f32 = 0.999;

/// Indices of refraction accepted.
const IOR: (f32, f32) = (0.01, 10.0);

/// The checks of one item: its origin, for the errors.
struct Item<'a> {
    origin: &'a Origin,
}

impl Item<'_> {
    fn fail<T>(&self, field: &'static str, message: String) -> Result<T, DescError> {
        Err(DescError::new(self.origin, field, message))
    }

    /// A position within [`limits::MAX_COORDINATE`].
    /// Checks that `index` names one of the description's `count` items
    /// of a kind (`what`: "material", "texture").
    fn exists(
        &self,
        field: &'static str,
        what: &str,
        index: u32,
        count: usize,
    ) -> Result<(), DescError> {
        if (index as usize) < count {
            return Ok(());
        }
        self.fail(
            field,
            format!("{what} {index} does not exist (the scene has {count})"),
        )
    }

    fn point(&self, field: &'static str, v: Vec3) -> Result<(), DescError> {
        limits::check_coordinates(&format!("`{field}`"), v).or_else(|m| self.fail(field, m))
    }

    /// A unit direction.
    fn direction(&self, field: &'static str, v: Vec3) -> Result<(), DescError> {
        if v.is_finite() && (v.length() - 1.0).abs() < 1e-3 {
            return Ok(());
        }
        self.fail(field, format!("`{field}` must be a non-zero direction"))
    }

    /// A number in `[lo, hi]`, described by `what` in the error.
    fn number(
        &self,
        field: &'static str,
        v: f32,
        (lo, hi): (f32, f32),
        what: &str,
    ) -> Result<(), DescError> {
        if v.is_finite() && v >= lo && v <= hi {
            return Ok(());
        }
        self.fail(field, format!("`{field}` must be {what}, got {v}"))
    }

    /// A non-negative finite colour, at most 1 per channel if `fraction`.
    fn color(&self, field: &'static str, c: Rgb, fraction: bool) -> Result<(), DescError> {
        let ok = c
            .to_array()
            .iter()
            .all(|x| x.is_finite() && *x >= 0.0 && (!fraction || *x <= 1.0));
        if ok {
            return Ok(());
        }
        let what = if fraction {
            "between 0 and 1"
        } else {
            "non-negative and finite"
        };
        self.fail(
            field,
            format!(
                "`{field}` must be {what} in every channel, got {:?}",
                c.to_array()
            ),
        )
    }

    /// An emitted quantity: non-negative, finite, at most
    /// [`limits::MAX_EMISSION`].
    fn emission(&self, field: &'static str, c: Rgb) -> Result<(), DescError> {
        self.color(field, c, false)?;
        limits::check_emission(&format!("`{field}`"), c).or_else(|m| self.fail(field, m))
    }

    /// A box with `min` below `max` on every axis.
    fn bounds(&self, field: &'static str, b: &Bounds) -> Result<(), DescError> {
        self.point(field, b.min)?;
        self.point(field, b.max)?;
        if b.min.cmplt(b.max).all() {
            return Ok(());
        }
        self.fail(
            field,
            format!(
                "box `min` {:?} must be below `max` {:?} on every axis",
                b.min.to_array(),
                b.max.to_array()
            ),
        )
    }

    /// A phase function's asymmetry in [−0.999, 0.999].
    fn phase(&self, phase: &PhaseFunction) -> Result<(), DescError> {
        match *phase {
            PhaseFunction::Isotropic => Ok(()),
            PhaseFunction::HenyeyGreenstein { g } => {
                self.number("g", g, (-MAX_ASYMMETRY, MAX_ASYMMETRY), "in (−1, 1)")
            }
        }
    }
}

impl SceneDesc {
    /// Checks the whole description; the first error found, at its item's
    /// origin ([`SceneDesc::errors`] gives them all).
    /// [`Scene::build`](crate::scene::Scene::build) refuses a description
    /// that does not pass.
    pub fn validate(&self) -> Result<(), DescError> {
        match self.errors().into_iter().next() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Every error of the description, each at its item's origin, in the
    /// order camera, render settings, materials, shapes, lights, fog,
    /// media: the first of each item (an item's later values are not
    /// checked once one is wrong).
    pub fn errors(&self) -> Vec<DescError> {
        let mut errors = Vec::new();
        let mut check = |result: Result<(), DescError>| {
            if let Err(e) = result {
                errors.push(e);
            }
        };
        check(self.validate_camera());
        let item = Item {
            origin: &self.settings_origin,
        };
        check(item.emission("background", self.background));
        check(
            self.settings
                .check_ranges()
                .or_else(|e| item.fail(e.setting, e.message)),
        );
        for material in &self.materials {
            check(validate_material(&material.value, &material.origin));
        }
        let mut lights = 0;
        let mut counted = Ok(());
        for shape in &self.shapes {
            check(self.validate_shape(shape));
            if self.is_emissive(shape.material) {
                // Each quad and sphere is a light; the triangles together
                // are one mesh light.
                let triangles = shape
                    .shapes
                    .iter()
                    .filter(|s| matches!(s, Shape::Triangle(_)))
                    .count();
                lights += shape.shapes.len() - triangles + usize::from(triangles > 0);
                if lights > limits::MAX_LIGHTS && counted.is_ok() {
                    counted = Err(too_many_lights(&shape.origin, "material"));
                }
            }
        }
        for light in &self.lights {
            lights += 1;
            if lights > limits::MAX_LIGHTS && counted.is_ok() {
                counted = Err(too_many_lights(&light.origin, "type"));
            }
            check(validate_light(&light.value, &light.origin));
        }
        check(counted);
        check(self.validate_light_groups());
        check(self.validate_environment());
        if let Some(fog) = &self.fog {
            check(validate_fog(&fog.value, &fog.origin));
        }
        if let Some(medium) = self.media.get(MAX_VOLUMES) {
            check(Err(DescError::new(
                &medium.origin,
                "sigma_t",
                format!("a scene may hold at most {MAX_VOLUMES} media"),
            )));
        }
        for medium in &self.media {
            check(medium.validate());
        }
        errors
    }

    fn validate_camera(&self) -> Result<(), DescError> {
        let camera = &self.camera.value;
        let item = Item {
            origin: &self.camera.origin,
        };
        item.point("position", camera.position)?;
        item.point("look_at", camera.look_at)?;
        item.number(
            "fov_y_deg",
            camera.fov.degrees(),
            FieldOfView::RANGE_DEG,
            FieldOfView::RANGE_WORDS,
        )?;
        if let Aperture::ThinLens {
            radius,
            focus_distance,
        } = camera.aperture
        {
            let lengths = (f32::MIN_POSITIVE, limits::MAX_COORDINATE);
            let words = "a length > 0 within the coordinate limit";
            item.number("aperture_radius", radius, lengths, words)?;
            item.number("focus_distance", focus_distance, lengths, words)?;
        }
        camera.check().or_else(|m| item.fail("look_at", m))
    }

    fn validate_shape(&self, shape: &ShapeDesc) -> Result<(), DescError> {
        let item = Item {
            origin: &shape.origin,
        };
        item.exists("material", "material", shape.material, self.materials.len())?;
        for s in &shape.shapes {
            match s {
                Shape::Sphere(sphere) => {
                    item.point("center", sphere.center)?;
                    item.number(
                        "radius",
                        sphere.radius,
                        (f32::MIN_POSITIVE, limits::MAX_COORDINATE),
                        "a length between 1.2e-38 and 1e9",
                    )?;
                }
                Shape::Quad(quad) => {
                    for corner in [quad.origin, quad.origin + quad.edge_u + quad.edge_v] {
                        item.point("corners", corner)?;
                    }
                }
                Shape::Triangle(t) => {
                    for v in [t.v0, t.v0 + t.e1, t.v0 + t.e2] {
                        item.point("file", v)?;
                    }
                }
            }
        }
        self.validate_mesh_attributes(shape, &item)
    }
}

/// The names a surface's reflectances go by in the native format: a
/// diffuse material's `reflectance` is its diffuse albedo, a mirror's and a
/// glossy one's its specular albedo (with `diffuse` beside it).
fn validate_surface(s: &Surface, item: &Item) -> Result<(), DescError> {
    let is_diffuse = s.specular == Rgb::ZERO && s.roughness == 0.0;
    let diffuse_key = if is_diffuse { "reflectance" } else { "diffuse" };
    item.color(diffuse_key, s.diffuse, true)?;
    item.color("reflectance", s.specular, true)?;
    item.number("roughness", s.roughness, (0.0, 1.0), "in [0, 1]")?;
    item.number("coat", s.coat.reflectance, (0.0, 1.0), "in [0, 1]")?;
    item.number("coat_roughness", s.coat.roughness, (0.0, 1.0), "in [0, 1]")
}

fn validate_material(material: &Material, origin: &Origin) -> Result<(), DescError> {
    let item = Item { origin };
    match material {
        Material::Opaque(surface) => validate_surface(surface, &item),
        Material::Emissive {
            radiance, surface, ..
        } => {
            item.emission("radiance", *radiance)?;
            validate_surface(surface, &item)
        }
        Material::LampFace { radiance } => item.emission("radiance", *radiance),
        Material::Glass(glass) => {
            item.color("color", glass.color, true)?;
            item.number("alpha", glass.alpha, (0.0, 1.0), "an opacity in [0, 1]")
        }
        Material::Dielectric { ior, absorption } => {
            item.number("ior", *ior, IOR, "an index of refraction in [0.01, 10]")?;
            item.color("absorption", *absorption, false)
        }
    }
}

fn validate_light(light: &LightDesc, origin: &Origin) -> Result<(), DescError> {
    let item = Item { origin };
    match light {
        LightDesc::Point(p) => {
            item.point("position", p.position)?;
            item.emission("intensity", p.intensity)
        }
        LightDesc::Spot(s) => {
            item.point("position", s.position)?;
            item.direction("direction", s.direction)?;
            // cos θc ∈ [0, 1): a half-angle in (0°, 90°].
            if !(s.cos_cutoff >= 0.0 && s.cos_cutoff < 1.0) {
                return item.fail(
                    "cutoff_deg",
                    format!(
                        "`cutoff_deg` must be a half-angle in (0°, 90°], got {}°",
                        s.cos_cutoff.acos().to_degrees()
                    ),
                );
            }
            if let crate::lights::SpotProfile::Smooth { cos_inner } = s.profile
                && !(cos_inner > s.cos_cutoff && cos_inner <= 1.0)
            {
                return item.fail(
                    "inner_deg",
                    format!(
                        "`inner_deg` must be an angle in [0°, cutoff_deg), got {}°",
                        cos_inner.clamp(-1.0, 1.0).acos().to_degrees()
                    ),
                );
            }
            item.emission("intensity", s.intensity)
        }
        LightDesc::Directional(d) => {
            item.direction("direction", d.direction)?;
            item.emission("irradiance", d.irradiance)
        }
        // A map's texels were checked when it was made.
        LightDesc::Environment(e) => item.emission("scale", e.scale),
    }
}

impl SceneDesc {
    /// At most one environment light, and no background beside it (the
    /// environment is what rays leaving the scene see).
    fn validate_environment(&self) -> Result<(), DescError> {
        let mut environments = self
            .lights
            .iter()
            .filter(|l| matches!(l.value, LightDesc::Environment(_)));
        let Some(first) = environments.next() else {
            return Ok(());
        };
        if let Some(second) = environments.next() {
            return Err(DescError::new(
                &second.origin,
                "type",
                "a scene may hold one environment light; this is a second",
            ));
        }
        if self.background != Rgb::ZERO {
            return Err(DescError::new(
                &first.origin,
                "type",
                "a scene with an environment light may not also set a `background`: \
                 the environment is what rays leaving the scene see",
            ));
        }
        Ok(())
    }
}

fn validate_fog(fog: &Fog, origin: &Origin) -> Result<(), DescError> {
    let item = Item { origin };
    item.number(
        "sigma_t",
        fog.sigma_t,
        (0.0, f32::MAX),
        "a non-negative density",
    )?;
    limits::check_fog_extinction(fog.sigma_t).or_else(|e| item.fail("sigma_t", e))?;
    item.color("albedo", fog.albedo, false)?;
    limits::check_fog_albedo(fog.albedo).or_else(|e| item.fail("albedo", e))?;
    item.phase(&fog.phase)?;
    match &fog.bounds {
        Some(b) => item.bounds("box", b),
        None => Ok(()),
    }
}

impl MediumDesc {
    /// Refuses a medium out of range or that cannot be tracked: a
    /// non-uniform density without a region to map it to, a flat mesh, a
    /// medium filling all space so thin that its mean free path passes the
    /// coordinate limit, or a density whose majorant makes delta tracking
    /// take more than [`limits::MAX_MAJORANT_DEPTH`] steps across its box.
    pub fn validate(&self) -> Result<(), DescError> {
        let item = Item {
            origin: &self.origin,
        };
        let sigma_t = self.sigma_t;
        item.color("sigma_t", sigma_t, false)?;
        limits::check_extinction_channels(sigma_t).or_else(|e| item.fail("sigma_t", e))?;
        item.color("albedo", self.albedo, true)?;
        item.phase(&self.phase)?;
        let uniform = self.density == Density::Uniform;
        // The box the density field is mapped to (infinite everywhere).
        let field_box = self.region.bounds();
        match &self.region {
            RegionDesc::Everywhere if !uniform => {
                return item.fail(
                    "density",
                    "a volume with a non-uniform density needs a `box` or a `mesh`".into(),
                );
            }
            RegionDesc::Box(b) => item.bounds("box", b)?,
            RegionDesc::Mesh(triangles) => {
                for t in triangles {
                    for v in [t.v0, t.v0 + t.e1, t.v0 + t.e2] {
                        item.point("mesh", v)?;
                    }
                }
                if field_box.extent().min_element() <= 0.0 {
                    return item.fail("mesh", "the mesh is flat: it encloses no volume".into());
                }
            }
            RegionDesc::Everywhere => {}
        }
        if self.region == RegionDesc::Everywhere
            && sigma_t.max_element() > 0.0
            && sigma_t.min_element() < limits::MIN_UNBOUNDED_EXTINCTION
        {
            return item.fail(
                "sigma_t",
                format!(
                    "`sigma_t` {:?} is too thin for a medium that fills all space: its mean free path would exceed {:e} units, beyond the coordinate limit; use at least {:e} (or 0), or give the medium a `box`",
                    sigma_t.to_array(),
                    limits::MAX_COORDINATE,
                    limits::MIN_UNBOUNDED_EXTINCTION
                ),
            );
        }
        if let Some(emission) = &self.emission {
            self.validate_emission(&item, emission)?;
        }
        if !uniform {
            // Tracking cost: tentative collisions to cross the box where
            // the density is far below its majorant.
            let peak = self.density.max_in(Vec3::ZERO, Vec3::ONE);
            let depth = peak * sigma_t.max_element() * field_box.extent().length();
            if depth.is_nan() || depth > limits::MAX_MAJORANT_DEPTH {
                return item.fail(
                    "sigma_t",
                    format!(
                        "the medium's largest extinction times its box's diagonal is {depth:.3e}, more than the {:e} a non-uniform density may reach: tracking would take about that many steps per ray",
                        limits::MAX_MAJORANT_DEPTH
                    ),
                );
            }
        }
        Ok(())
    }
}

impl MediumDesc {
    /// Emission in range: a bounded medium, a finite non-negative colour,
    /// temperatures `scale·value + offset` from 0 to
    /// [`limits::MAX_TEMPERATURE_K`].
    fn validate_emission(&self, item: &Item, emission: &Emission) -> Result<(), DescError> {
        if self.region == RegionDesc::Everywhere {
            return item.fail(
                "emission",
                "an emitting medium needs a `box` or a `mesh` (one filling all space would emit without bound)".into(),
            );
        }
        item.emission("emission", emission.color)?;
        let Some(b) = &emission.blackbody else {
            return Ok(());
        };
        let finite_at_least = |field: &'static str, v: f32, lo: f32, strict: bool| {
            if v.is_finite() && (v > lo || (!strict && v == lo)) {
                Ok(())
            } else {
                let relation = if strict { ">" } else { "≥" };
                item.fail(
                    field,
                    format!("`{field}` must be finite and {relation} {lo}, got {v}"),
                )
            }
        };
        finite_at_least("temperature_scale", b.scale, 0.0, true)?;
        finite_at_least("temperature_offset", b.offset, 0.0, false)?;
        finite_at_least("blackbody_intensity", b.intensity, 0.0, false)?;
        if let BlackbodyLaw::Cycles { tint } = b.law {
            if b.intensity > 1.0 {
                return item.fail(
                    "blackbody_intensity",
                    format!(
                        "`blackbody_intensity` mixes Cycles' constant and T⁴ terms and must lie in [0, 1], got {}",
                        b.intensity
                    ),
                );
            }
            item.emission("blackbody_tint", tint)?;
        }
        let hottest = b.scale * b.temperature.max_in(Vec3::ZERO, Vec3::ONE) + b.offset;
        if !(hottest.is_finite() && hottest <= limits::MAX_TEMPERATURE_K) {
            return item.fail(
                "temperature_scale",
                format!(
                    "the hottest point would be {hottest:e} K (`temperature_scale`·value + `temperature_offset`), above the {:e} K limit",
                    limits::MAX_TEMPERATURE_K
                ),
            );
        }
        Ok(())
    }
}

fn too_many_lights(origin: &Origin, field: &'static str) -> DescError {
    DescError::new(
        origin,
        field,
        format!(
            "a scene may hold at most {} lights (emissive quads, box faces and spheres count)",
            limits::MAX_LIGHTS
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::super::Sourced;
    use super::*;
    use crate::camera::CameraSpec;
    use crate::lights::{PointLight, SpotLight, SpotProfile};
    use crate::scene::Scene;
    use crate::shapes::Sphere;

    /// A description made in code, as an API user or a new loader would:
    /// one diffuse sphere under a point light.
    fn scene() -> SceneDesc {
        let camera = CameraSpec::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
        let mut desc = SceneDesc::new(Sourced::code(camera));
        let grey = desc.add_material(
            Material::Opaque(Surface::diffuse(Rgb::splat(0.5))),
            Origin::Code,
        );
        let sphere = Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        desc.add_shapes(vec![Shape::Sphere(sphere)], grey, Origin::Code);
        let light = PointLight {
            luminaire: None,
            position: Vec3::new(0.0, 3.0, 0.0),
            intensity: Rgb::splat(10.0),
        };
        desc.add_light(LightDesc::Point(light), Origin::Code);
        desc
    }

    /// The error `Scene::build` gives after `change`, by field.
    fn refused(change: impl FnOnce(&mut SceneDesc)) -> &'static str {
        let mut desc = scene();
        change(&mut desc);
        let e = Scene::build(&desc).err().expect("refused");
        assert_eq!(desc.validate(), Err(e.clone()));
        assert_eq!(Scene::from_desc(desc.clone()).err(), Some(e.clone()));
        e.field
    }

    #[test]
    fn every_error_is_reported_with_its_origin() {
        let mut desc = scene();
        desc.shapes[0].material = 7;
        desc.materials[0].origin = Origin::Element {
            file: std::sync::Arc::from(std::path::Path::new("made.py")),
            path: "materials[0]".into(),
        };
        desc.materials[0].value = Material::Dielectric {
            ior: -1.0,
            absorption: Rgb::ZERO,
        };
        desc.settings.spp = 0;
        let fields: Vec<&str> = desc.errors().iter().map(|e| e.field).collect();
        assert_eq!(fields, ["spp", "ior", "material"]);
        assert_eq!(desc.validate().unwrap_err().field, "spp");
        assert!(scene().errors().is_empty());
    }

    #[test]
    fn a_valid_description_builds() {
        let desc = scene();
        assert_eq!(desc.validate(), Ok(()));
        let scene = Scene::build(&desc).expect("builds");
        assert_eq!(scene.lights.len(), 1);
        let moved = Scene::from_desc(desc).expect("builds");
        assert_eq!(moved.lights, scene.lights);
        assert_eq!(moved.geometry.primitives(), scene.geometry.primitives());
    }

    #[test]
    fn every_kind_of_item_is_checked() {
        let origin = Origin::Element {
            file: std::sync::Arc::from(std::path::Path::new("made.py")),
            path: "shapes[0]".into(),
        };
        let mut desc = scene();
        desc.shapes[0].origin = origin.clone();
        desc.shapes[0].shapes[0] = Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: f32::NAN,
        });
        let e = desc.validate().unwrap_err();
        assert_eq!((e.field, &e.origin), ("radius", &origin));
        assert!(
            e.to_string().starts_with("made.py: shapes[0]: `radius`"),
            "{e}"
        );

        assert_eq!(refused(|d| d.shapes[0].material = 7), "material");
        assert_eq!(
            refused(|d| d.materials[0].value = Material::Dielectric {
                ior: 0.0,
                absorption: Rgb::ZERO
            }),
            "ior"
        );
        assert_eq!(
            refused(|d| d.camera.value.position = Vec3::splat(f32::INFINITY)),
            "position"
        );
        assert_eq!(
            refused(|d| d.camera.value.look_at = Vec3::new(0.0, 0.0, 5.0)),
            "look_at"
        );
        assert_eq!(refused(|d| d.background = Rgb::splat(-1.0)), "background");
        assert_eq!(refused(|d| d.settings.spp = 0), "spp");
        let spot = SpotLight {
            gobo: None,
            luminaire: None,
            position: Vec3::Y,
            direction: -Vec3::Y,
            cos_cutoff: 1.0,
            profile: SpotProfile::Linear,
            intensity: Rgb::ONE,
        };
        assert_eq!(
            refused(|d| d.add_light(LightDesc::Spot(spot), Origin::Code)),
            "cutoff_deg"
        );
        let fog = Fog {
            sigma_t: 0.1,
            albedo: Rgb::ONE,
            phase: PhaseFunction::HenyeyGreenstein { g: 1.0 },
            bounds: None,
        };
        assert_eq!(refused(|d| d.fog = Some(Sourced::code(fog))), "g");
        let smoke = MediumDesc {
            sigma_t: Rgb::ONE,
            albedo: Rgb::splat(0.9),
            phase: PhaseFunction::Isotropic,
            density: Density::Noise(crate::media::noise::SmokeNoise {
                frequency: 3.0,
                octaves: 2,
                bias: 0.0,
                seed: 1,
            }),
            region: RegionDesc::Everywhere,
            emission: None,
            origin: Origin::Code,
        };
        assert_eq!(refused(|d| d.media.push(smoke)), "density");
    }

    /// An emission texture lies on an emissive triangle mesh, names a
    /// texture of the scene and has one coordinate triple per triangle;
    /// an emitter's reflecting surface is checked as any surface.
    #[test]
    fn emission_maps_and_reflecting_emitters_are_checked() {
        use crate::description::{EmissionMap, MeshAttributes};
        use crate::shapes::Triangle;
        use crate::texture::{Texture, Wrap};
        let triangle = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y).expect("triangle");
        // A glowing triangle with a 1×1 texture, then `change`.
        let glowing = |change: fn(&mut SceneDesc)| {
            refused(|d| {
                let white = Texture::new(1, 1, vec![[255; 3]], [Wrap::Repeat; 2]).expect("texture");
                let texture = d.add_texture(std::sync::Arc::new(white), Origin::Code);
                let glow = d.add_material(Material::emitter(Rgb::ONE, false), Origin::Code);
                let attributes = MeshAttributes {
                    emission_map: Some(EmissionMap {
                        texture,
                        uvs: vec![[glam::Vec2::ZERO; 3]],
                    }),
                    ..MeshAttributes::default()
                };
                d.add_mesh(vec![triangle], attributes, glow, Origin::Code);
                change(d);
            })
        };
        fn map(d: &mut SceneDesc) -> &mut EmissionMap {
            d.shapes[1].emission_map.as_mut().expect("map")
        }
        assert_eq!(glowing(|d| map(d).texture = 9), "emission_map");
        assert_eq!(glowing(|d| map(d).uvs.clear()), "emission_map");
        assert_eq!(glowing(|d| map(d).uvs[0][1].x = f32::NAN), "emission_map");
        // On the grey sphere: not a mesh, and not emissive.
        assert_eq!(
            glowing(|d| d.shapes[0].emission_map = d.shapes[1].emission_map.clone()),
            "emission_map"
        );
        assert_eq!(glowing(|d| d.shapes[1].material = 0), "emission_map");
        assert_eq!(
            glowing(|d| d.materials[1].value = Material::Emissive {
                radiance: Rgb::ONE,
                two_sided: false,
                surface: Surface::diffuse(Rgb::splat(2.0)),
            }),
            "reflectance"
        );
    }
}
