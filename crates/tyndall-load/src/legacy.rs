//! The paper's scene format: the course code base's extended .obj
//! (docs/scene-format.md, "The paper's legacy format"), with the paper's `c` (spotlight cutoff) and
//! `alpha` (glass opacity) tokens.
//!
//! Tokens are whitespace-separated and newlines are not significant. A
//! `material` block is open from the `material` token until the next
//! statement that is not one of its fields. A `c` followed by another
//! field of an open block belongs to the material; a `c` outside a block
//! applies to the emissive faces that follow (until the next `c`). A `c`
//! that ends a block's fields could be either (`TrailingCutoff`).

use crate::source::{SceneError, SourceText};
use glam::Vec3;
use std::path::Path;
use std::sync::Arc;
use tyndall::camera::{CameraSpec, FieldOfView};
use tyndall::color::{Rgb, srgb_to_linear};
use tyndall::description::{LightDesc, Origin, SceneDesc, Sourced};
use tyndall::glass::{Glass, GlassModel};
use tyndall::lights::{SpotLight, SpotProfile};
use tyndall::limits;
use tyndall::materials::{Material, Surface};
use tyndall::settings::{IntegratorKind, RenderSettings};
use tyndall::shapes::{Bounds, Quad, Shape, Sphere, Triangle};

/// Options for loading legacy files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LegacyOptions {
    /// Make quads two-sided (the course code's switch); one-sided by default.
    pub two_sided: bool,
}

/// Loads a legacy .obj scene.
pub fn load(path: &Path, options: LegacyOptions) -> Result<SceneDesc, SceneError> {
    parse(&SourceText::read(path)?, options)
}

#[derive(Clone, Copy, Debug)]
struct Token<'a> {
    text: &'a str,
    offset: usize,
}

#[derive(Clone, Debug, Default)]
struct LegacyMaterial {
    diffuse: Rgb,
    reflective: Rgb,
    roughness: f32,
    emitted: Rgb,
    alpha: f32,
    cutoff_deg: Option<f32>,
    textured: bool,
    /// Byte offset of its `material` token.
    offset: usize,
}

struct Parser<'a> {
    source: &'a SourceText,
    tokens: Vec<Token<'a>>,
    next: usize,
}

impl<'a> Parser<'a> {
    fn new(source: &'a SourceText) -> Self {
        let text = source.text.as_str();
        let mut tokens = Vec::new();
        let mut start = None;
        for (i, ch) in text.char_indices() {
            match (ch.is_whitespace(), start) {
                (true, Some(s)) => {
                    tokens.push(Token {
                        text: &text[s..i],
                        offset: s,
                    });
                    start = None;
                }
                (false, None) => start = Some(i),
                _ => {}
            }
        }
        if let Some(s) = start {
            tokens.push(Token {
                text: &text[s..],
                offset: s,
            });
        }
        Self {
            source,
            tokens,
            next: 0,
        }
    }

    fn peek(&self) -> Option<Token<'a>> {
        self.tokens.get(self.next).copied()
    }

    fn bump(&mut self) -> Option<Token<'a>> {
        let t = self.peek();
        self.next += 1;
        t
    }

    fn end_offset(&self) -> usize {
        self.source.text.len()
    }

    fn error(&self, token: Option<Token>, message: impl Into<String>) -> SceneError {
        self.source
            .error_at(token.map_or(self.end_offset(), |t| t.offset), message)
    }

    /// A number for `what`; the error names what was expected.
    fn number(&mut self, what: &str) -> Result<f32, SceneError> {
        let t = self.bump();
        match t.map(|t| t.text.parse::<f32>()) {
            Some(Ok(v)) if v.is_finite() => Ok(v),
            Some(Ok(v)) => Err(self.error(
                t,
                format!("expected a finite number for {what}, found `{v}`"),
            )),
            Some(Err(_)) => Err(self.error(
                t,
                format!(
                    "expected a number for {what}, found `{}`",
                    t.map_or("", |t| t.text)
                ),
            )),
            None => Err(self.error(
                None,
                format!("expected a number for {what}, found the end of the file"),
            )),
        }
    }

    fn index(&mut self, what: &str) -> Result<(usize, Token<'a>), SceneError> {
        let t = self.bump();
        match t.map(|t| t.text.parse::<usize>()) {
            Some(Ok(v)) => Ok((v, t.expect("present"))),
            _ => Err(self.error(
                t,
                format!(
                    "expected a non-negative whole number for {what}, found {}",
                    describe(t)
                ),
            )),
        }
    }

    fn vec3(&mut self, what: &str) -> Result<Vec3, SceneError> {
        Ok(Vec3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }

    /// A position: three numbers within [`limits::MAX_COORDINATE`].
    fn position(&mut self, what: &str) -> Result<Vec3, SceneError> {
        let at = self.peek();
        let v = self.vec3(what)?;
        limits::check_coordinates(what, v).map_err(|m| self.error(at, m))?;
        Ok(v)
    }

    fn color(&mut self, what: &str) -> Result<Rgb, SceneError> {
        let at = self.peek();
        let c = self.vec3(what)?;
        if c.min_element() < 0.0 {
            return Err(self.error(
                at,
                format!("{what} must be non-negative, got {:?}", c.to_array()),
            ));
        }
        Ok(c)
    }

    /// A reflectance: a colour in [0, 1] per channel. Above 1 a surface
    /// creates light; bounce after bounce its paths overflow to infinity
    /// (found by fuzzing: `diffuse 1e15 0.54 0.54` dropped samples as NaN).
    fn reflectance(&mut self, what: &str) -> Result<Rgb, SceneError> {
        let at = self.peek();
        let c = self.color(what)?;
        if c.max_element() > 1.0 {
            return Err(self.error(
                at,
                format!(
                    "{what} is a reflectance and must be at most 1 per channel, got {:?}",
                    c.to_array()
                ),
            ));
        }
        Ok(c)
    }

    /// A vector written `< x, y, z >` with any spacing, inside a camera block.
    fn bracketed(&mut self, what: &str) -> Result<Vec3, SceneError> {
        let first = self.peek();
        let Some(start) = first.filter(|t| t.text.starts_with('<')) else {
            return Err(self.error(
                first,
                format!(
                    "expected `< x, y, z >` for {what}, found {}",
                    describe(first)
                ),
            ));
        };
        let mut end = None;
        while let Some(t) = self.bump() {
            if t.text.contains('>') {
                end = Some(t.offset + t.text.find('>').expect("contains") + 1);
                break;
            }
        }
        let Some(end) = end else {
            return Err(self.error(first, format!("unclosed `<` in {what}: expected `>`")));
        };
        let inner = &self.source.text[start.offset + 1..end - 1];
        let parts: Vec<&str> = inner.split(',').map(str::trim).collect();
        let values: Vec<Option<f32>> = parts
            .iter()
            .map(|p| p.parse::<f32>().ok().filter(|v| v.is_finite()))
            .collect();
        match values.as_slice() {
            [Some(x), Some(y), Some(z)] => {
                let v = Vec3::new(*x, *y, *z);
                limits::check_coordinates(what, v)
                    .map_err(|m| self.source.error_at(start.offset, m))?;
                Ok(v)
            }
            _ => Err(self.source.error_at(
                start.offset,
                format!(
                    "expected three finite numbers `< x, y, z >` for {what}, found `<{inner}>`"
                ),
            )),
        }
    }
}

fn describe(t: Option<Token>) -> String {
    t.map_or("the end of the file".to_string(), |t| {
        format!("`{}`", t.text)
    })
}

struct Face {
    vertices: [usize; 4],
    material: usize,
    /// The `c` statements written before the face (an index into the
    /// parse's cutoff list: the first `statements` of them).
    statements: usize,
    token: usize,
}

/// A spotlight cutoff `c` read where a statement may stand.
struct Cutoff {
    value: f32,
    /// `Some` for a `c` that ends the fields of a material block: it could
    /// be that block's field or a statement for the faces that follow.
    trailing: Option<TrailingCutoff>,
}

/// A `c` right after the last field of material `material`'s block.
/// Newlines do not separate statements, so only the material tells the
/// two readings apart: the cutoff of an emissive material is that
/// material's (it makes its faces spots); a non-emissive material has no
/// use for a cutoff, so there it is the statement for the emissive faces
/// that follow. Either reading is warned about, with the token's place,
/// when the other would have given any face a different cutoff.
struct TrailingCutoff {
    material: usize,
    offset: usize,
}

/// Block fields: names that continue an open `material` block.
fn is_block_field(token: &str) -> bool {
    matches!(
        token,
        "diffuse" | "texture_file" | "reflective" | "roughness" | "emitted" | "alpha"
    )
}

/// The cutoff each face gets when `as_statement[i]` says how cutoff `i`
/// is read: a material's own cutoff (its field, or a trailing `c` read
/// as its field) wins over the last statement before the face, as in the
/// paper's loader.
fn face_cutoffs(
    faces: &[Face],
    materials: &[LegacyMaterial],
    cutoffs: &[Cutoff],
    as_statement: &[bool],
) -> Vec<Option<f32>> {
    let mut own: Vec<Option<f32>> = materials.iter().map(|m| m.cutoff_deg).collect();
    for (c, statement) in cutoffs.iter().zip(as_statement) {
        if let (Some(t), false) = (&c.trailing, statement) {
            own[t.material] = Some(c.value);
        }
    }
    faces
        .iter()
        .map(|f| {
            own[f.material].or_else(|| {
                (0..f.statements)
                    .rev()
                    .find(|&i| as_statement[i])
                    .map(|i| cutoffs[i].value)
            })
        })
        .collect()
}

/// Parses legacy text. Quads are one-sided unless `options.two_sided`.
pub fn parse(source: &SourceText, options: LegacyOptions) -> Result<SceneDesc, SceneError> {
    let mut p = Parser::new(source);
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut materials: Vec<LegacyMaterial> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    let mut spheres: Vec<(Sphere, usize, usize)> = Vec::new();
    let mut active: Option<usize> = None;
    let mut open_block = false;
    let mut cutoffs: Vec<Cutoff> = Vec::new();
    let mut background = Rgb::ZERO;
    let mut camera: Option<CameraSpec> = None;
    let mut warnings = Vec::new();

    while let Some(tok) = p.bump() {
        let in_block = open_block;
        open_block = false;
        let block_field = is_block_field(tok.text) || (tok.text == "c" && in_block);
        if block_field {
            let Some(m) = materials.last_mut().filter(|_| in_block) else {
                return Err(p.error(
                    Some(tok),
                    format!(
                        "`{}` must follow a `material` line (it is a material field)",
                        tok.text
                    ),
                ));
            };
            match tok.text {
                "diffuse" => m.diffuse = p.reflectance("`diffuse`")?,
                "texture_file" => {
                    p.bump().ok_or_else(|| {
                        p.error(None, "expected a file name after `texture_file`")
                    })?;
                    m.diffuse = Rgb::splat(0.5);
                    m.textured = true;
                }
                "reflective" => m.reflective = p.reflectance("`reflective`")?,
                "roughness" => {
                    let at = p.peek();
                    let r = p.number("`roughness`")?;
                    if !(0.0..=1.0).contains(&r) {
                        return Err(p.error(at, format!("`roughness` must be in [0, 1], got {r}")));
                    }
                    materials.last_mut().expect("open block").roughness = r;
                }
                "emitted" => {
                    let at = p.peek();
                    let c = p.color("`emitted`")?;
                    limits::check_emission("`emitted`", c).map_err(|e| p.error(at, e))?;
                    materials.last_mut().expect("open block").emitted = c;
                }
                "alpha" => {
                    let at = p.peek();
                    let a = p.number("`alpha`")?;
                    if !(0.0..=1.0).contains(&a) {
                        return Err(
                            p.error(at, format!("`alpha` must be an opacity in [0, 1], got {a}"))
                        );
                    }
                    materials.last_mut().expect("open block").alpha = a;
                }
                _ => {
                    let value = cutoff(&mut p)?;
                    if p.peek().is_some_and(|t| is_block_field(t.text)) {
                        materials.last_mut().expect("open block").cutoff_deg = Some(value);
                    } else {
                        cutoffs.push(Cutoff {
                            value,
                            trailing: Some(TrailingCutoff {
                                material: materials.len() - 1,
                                offset: tok.offset,
                            }),
                        });
                    }
                }
            }
            open_block = true;
            continue;
        }
        match tok.text {
            "material" => {
                materials.push(LegacyMaterial {
                    alpha: 1.0,
                    offset: tok.offset,
                    ..Default::default()
                });
                open_block = true;
            }
            "v" => vertices.push(p.position("a vertex `v x y z`")?),
            "vt" => {
                p.number("texture coordinate s")?;
                p.number("texture coordinate t")?;
            }
            "m" => {
                let (i, t) = p.index("the material number of `m`")?;
                if i >= materials.len() {
                    return Err(p.error(Some(t), format!("material {i} is not defined ({} materials so far; they are numbered from 0)", materials.len())));
                }
                active = Some(i);
            }
            "c" => {
                let value = cutoff(&mut p)?;
                cutoffs.push(Cutoff {
                    value,
                    trailing: None,
                });
            }
            "f" => {
                let token = p.next - 1;
                let material = active.ok_or_else(|| {
                    p.error(
                        Some(tok),
                        "a face needs an active material: use `m i` first",
                    )
                })?;
                let mut v = [0usize; 4];
                for slot in &mut v {
                    let (i, t) = p.index("a vertex number of `f`")?;
                    if i == 0 || i > vertices.len() {
                        return Err(p.error(Some(t), format!("vertex {i} is not defined ({} vertices so far; they are numbered from 1)", vertices.len())));
                    }
                    *slot = i - 1;
                }
                faces.push(Face {
                    vertices: v,
                    material,
                    statements: cutoffs.len(),
                    token,
                });
            }
            "s" => {
                let material = active.ok_or_else(|| {
                    p.error(
                        Some(tok),
                        "a sphere needs an active material: use `m i` first",
                    )
                })?;
                let center = p.position("the sphere centre")?;
                let at = p.peek();
                let radius = p.number("the sphere radius")?;
                if !(radius > 0.0 && radius <= limits::MAX_COORDINATE) {
                    return Err(p.error(
                        at,
                        format!(
                            "sphere radius must be positive and at most {:e}, got {radius}",
                            limits::MAX_COORDINATE
                        ),
                    ));
                }
                spheres.push((Sphere { center, radius }, material, tok.offset));
            }
            "r" => {
                return Err(p.error(
                    Some(tok),
                    "cylinder rings (`r`) are not supported: model the ring as a mesh",
                ));
            }
            "background_color" => {
                let at = p.peek();
                let c = p.color("`background_color`")?;
                background = Rgb::new(
                    srgb_to_linear(c.x),
                    srgb_to_linear(c.y),
                    srgb_to_linear(c.z),
                );
                // Decoding raises values to the power 2.4: found by
                // fuzzing, `background_color 1e20 0 0` became infinite.
                limits::check_emission(
                    "`background_color` (decoded to linear radiance)",
                    background,
                )
                .map_err(|e| p.error(at, e))?;
            }
            "PerspectiveCamera" => camera = Some(perspective_camera(&mut p, tok)?),
            "OrthographicCamera" => {
                return Err(p.error(
                    Some(tok),
                    "`OrthographicCamera` is not supported: use a `PerspectiveCamera`",
                ));
            }
            other => {
                return Err(p.error(Some(tok), format!(
                    "unknown token `{other}`: expected a statement (v, vt, f, s, m, c, material, background_color, PerspectiveCamera)"
                )));
            }
        }
    }

    // How each `c` is read, and warnings where the other reading differs.
    let emissive = |m: usize| materials[m].emitted.max_element() > 0.0;
    let as_statement: Vec<bool> = cutoffs
        .iter()
        .map(|c| c.trailing.as_ref().is_none_or(|t| !emissive(t.material)))
        .collect();
    let face_cutoff = face_cutoffs(&faces, &materials, &cutoffs, &as_statement);
    let emissive_faces: Vec<usize> = (0..faces.len())
        .filter(|&i| emissive(faces[i].material))
        .collect();
    for (i, c) in cutoffs.iter().enumerate() {
        let Some(t) = &c.trailing else { continue };
        let mut other = as_statement.clone();
        other[i] = !other[i];
        let other_cutoff = face_cutoffs(&faces, &materials, &cutoffs, &other);
        let differ = emissive_faces
            .iter()
            .filter(|&&f| face_cutoff[f] != other_cutoff[f])
            .count();
        if differ == 0 {
            continue;
        }
        let (line, column) = source.line_col(t.offset);
        let reading = if as_statement[i] {
            format!(
                "material {} does not emit, so it is read as a statement for the emissive faces that follow",
                t.material
            )
        } else {
            format!(
                "material {} emits, so it is read as that material's cutoff",
                t.material
            )
        };
        warnings.push(format!(
            "{}:{line}:{column}: `c {}` ends the fields of material {}'s block; newlines do not separate statements, so it may be that material's cutoff or a statement: {reading}. The other reading would change {differ} emissive face(s). Write it after `m i` for a statement, or before the block's `emitted` for the material's",
            source.path.display(),
            c.value,
            t.material,
        ));
    }

    let camera = match camera {
        Some(c) => c,
        None => {
            let camera = default_camera(&vertices, &spheres);
            // Far from the origin a small scene's offset camera can round
            // onto its target (issue 11: every ray NaN, a black image).
            camera.check().map_err(|m| {
                source.error(format!(
                    "the default camera (the file has no `PerspectiveCamera`) cannot be placed: {m}; give a `PerspectiveCamera`"
                ))
            })?;
            camera
        }
    };
    let file: Arc<Path> = Arc::from(source.path.as_path());
    let at = |offset: usize| {
        let (line, column) = source.line_col(offset);
        Origin::Location {
            file: file.clone(),
            line,
            column,
        }
    };
    let mut desc = SceneDesc::new(Sourced::new(
        camera,
        Origin::Element {
            file: file.clone(),
            path: "PerspectiveCamera".into(),
        },
    ));
    desc.background = background;
    desc.glass.model = GlassModel::Blend;
    let one_sided = !options.two_sided;
    let ids: Vec<u32> = materials
        .iter()
        .map(|m| {
            let material = if m.emitted.max_element() > 0.0 {
                Material::Emissive {
                    radiance: m.emitted,
                    two_sided: !one_sided,
                }
            } else if m.alpha < 1.0 {
                Material::Glass(Glass {
                    color: m.diffuse.min(Rgb::ONE),
                    alpha: m.alpha,
                })
            } else {
                Material::Opaque(Surface {
                    diffuse: m.diffuse,
                    specular: m.reflective,
                    roughness: m.roughness,
                })
            };
            desc.add_material(material, at(m.offset))
        })
        .collect();
    if materials.iter().any(|m| m.textured) {
        warnings.push(format!(
            "{}: texture files are not supported; textured materials are drawn mid-grey",
            source.path.display()
        ));
    }
    // The lamp-face material of each emissive material used by spots.
    let mut lamp_ids: Vec<Option<u32>> = vec![None; materials.len()];
    for (face, cutoff) in faces.iter().zip(&face_cutoff) {
        let m = &materials[face.material];
        let c = face.vertices.map(|i| vertices[i]);
        let offset = p.tokens[face.token].offset;
        let quad = Quad::from_corners(c, one_sided);
        if m.emitted.max_element() > 0.0 {
            let quad = quad.map_err(|e| source.error_at(offset, format!("emissive face: {e}")))?;
            match *cutoff {
                Some(cutoff) => {
                    // The spot's intensity is radiance × area (W/sr).
                    let intensity = m.emitted * quad.area();
                    limits::check_emission(
                        "the spotlight's intensity (`emitted` × face area)",
                        intensity,
                    )
                    .map_err(|e| source.error_at(offset, format!("emissive face: {e}")))?;
                    // The quad is the lamp seen by the camera; the spot
                    // carries its light into the scene (counted once).
                    let lamp = *lamp_ids[face.material].get_or_insert_with(|| {
                        let lamp = Material::LampFace {
                            radiance: m.emitted,
                        };
                        desc.add_material(lamp, at(m.offset))
                    });
                    desc.add_shapes(vec![Shape::Quad(quad)], lamp, at(offset));
                    let spot = SpotLight {
                        position: quad.centroid(),
                        direction: quad.normal,
                        cos_cutoff: cutoff.to_radians().cos(),
                        profile: SpotProfile::Linear,
                        intensity,
                    };
                    desc.add_light(LightDesc::Spot(spot), at(offset));
                }
                None => desc.add_quad_light(quad, m.emitted, !one_sided, at(offset)),
            }
            continue;
        }
        match quad {
            Ok(q) => desc.add_shapes(vec![Shape::Quad(q)], ids[face.material], at(offset)),
            Err(_) => {
                // A planar or non-planar general quad: two triangles.
                let make = if one_sided {
                    Triangle::new_one_sided
                } else {
                    Triangle::new
                };
                let tris = [make(c[0], c[1], c[2]), make(c[0], c[2], c[3])];
                if tris.iter().all(Option::is_none) {
                    return Err(source.error_at(
                        offset,
                        "the face has no area (its vertices are collinear or repeated)",
                    ));
                }
                let triangles = tris.into_iter().flatten().map(Shape::Triangle).collect();
                desc.add_shapes(triangles, ids[face.material], at(offset));
            }
        }
    }
    for &(sphere, material, offset) in &spheres {
        desc.add_shapes(vec![Shape::Sphere(sphere)], ids[material], at(offset));
    }
    desc.settings = RenderSettings {
        integrator: IntegratorKind::March,
        ..RenderSettings::default()
    };
    if let Some(e) = source.locate_all(&desc.errors()) {
        return Err(e);
    }
    warnings.extend(desc.lighting_warnings());
    desc.warnings = warnings;
    Ok(desc)
}

fn cutoff(p: &mut Parser) -> Result<f32, SceneError> {
    let at = p.peek();
    let c = p.number("the spotlight cutoff `c`")?;
    if !(c > 0.0 && c <= 90.0) {
        return Err(p.error(
            at,
            format!("spotlight cutoff `c` must be an angle in (0, 90] degrees, got {c}"),
        ));
    }
    Ok(c)
}

fn perspective_camera(p: &mut Parser, tok: Token) -> Result<CameraSpec, SceneError> {
    let open = p.bump();
    if open.map(|t| t.text) != Some("{") {
        return Err(p.error(
            open,
            format!(
                "expected `{{` after `PerspectiveCamera`, found {}",
                describe(open)
            ),
        ));
    }
    let (mut position, mut look_at, mut up, mut angle) = (None, None, None, None);
    loop {
        let key = p.bump();
        match key.map(|t| t.text) {
            Some("}") => break,
            Some("camera_position") => position = Some(p.bracketed("`camera_position`")?),
            Some("point_of_interest") => look_at = Some(p.bracketed("`point_of_interest`")?),
            Some("up") => up = Some(p.bracketed("`up`")?),
            Some("angle") => {
                let at = p.peek();
                let a = p.number("`angle`")?;
                if !FieldOfView::in_range(a) {
                    return Err(p.error(
                        at,
                        format!(
                            "camera `angle` must be {}, got {a}",
                            FieldOfView::RANGE_WORDS
                        ),
                    ));
                }
                angle = Some(a);
            }
            _ => {
                return Err(p.error(key, format!(
                    "expected a camera field (camera_position, point_of_interest, up, angle) or `}}`, found {}",
                    describe(key)
                )));
            }
        }
    }
    let missing = |name: &str| p.error(Some(tok), format!("`PerspectiveCamera` needs `{name}`"));
    let spec = CameraSpec {
        position: position.ok_or_else(|| missing("camera_position"))?,
        look_at: look_at.ok_or_else(|| missing("point_of_interest"))?,
        up: up.ok_or_else(|| missing("up"))?,
        fov: FieldOfView::ShorterSide(angle.ok_or_else(|| missing("angle"))?),
    };
    spec.check().map_err(|m| p.error(Some(tok), m))?;
    Ok(spec)
}

/// The legacy format (docs/scene-format.md): without a camera, look at the centre of the scene's
/// bounds from 4 × its largest dimension along +z, 20° field of view.
fn default_camera(vertices: &[Vec3], spheres: &[(Sphere, usize, usize)]) -> CameraSpec {
    let bounds = vertices.iter().fold(Bounds::EMPTY, |b, v| b.include(*v));
    let bounds = spheres
        .iter()
        .fold(bounds, |b, (s, _, _)| b.union(s.bounds()));
    let (center, size) = if bounds.is_empty() {
        (Vec3::ZERO, 1.0)
    } else {
        (bounds.center(), bounds.extent().max_element().max(1e-3))
    };
    CameraSpec {
        position: center + Vec3::Z * (4.0 * size),
        look_at: center,
        up: Vec3::Y,
        fov: FieldOfView::ShorterSide(20.0),
    }
}
