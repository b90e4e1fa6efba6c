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

//! Phase 1 of reading a legacy file: its tokens read as statements —
//! vertices, material blocks, faces, spheres, spotlight cutoffs, the
//! background and the camera — each value checked as it is read, with
//! its byte offset for errors. A `c` inside a material block that another
//! field follows is that material's; one that ends a block's fields is
//! kept as a [`TrailingCutoff`] for phase 2 ([`super::cutoffs`]) to read.

use crate::source::{SceneError, SourceText};
use glam::Vec3;
use tyndall::camera::{Aperture, CameraSpec, FieldOfView};
use tyndall::color::{Rgb, srgb_to_linear};
use tyndall::limits;
use tyndall::shapes::Sphere;

/// Everything a legacy file states, in file order, before any `c` is
/// disambiguated or any scene item is built.
#[derive(Debug, Default)]
pub(super) struct Statements {
    /// The `v` positions, numbered from 1 by faces.
    pub vertices: Vec<Vec3>,
    /// The `material` blocks, numbered from 0 by `m`.
    pub materials: Vec<LegacyMaterial>,
    /// The `f` faces.
    pub faces: Vec<Face>,
    /// The `s` spheres.
    pub spheres: Vec<SphereStatement>,
    /// Every `c` read where a statement may stand, in file order.
    pub cutoffs: Vec<Cutoff>,
    /// `background_color`, decoded to linear radiance (black if absent).
    pub background: Rgb,
    /// The `PerspectiveCamera`, if the file has one.
    pub camera: Option<CameraSpec>,
}

/// An `s` statement: a sphere with the material active at it.
#[derive(Clone, Copy, Debug)]
pub(super) struct SphereStatement {
    pub sphere: Sphere,
    pub material: usize,
    /// Byte offset of its `s` token.
    pub offset: usize,
}

#[derive(Clone, Copy, Debug)]
struct Token<'a> {
    text: &'a str,
    offset: usize,
}

/// A `material` block's fields.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct LegacyMaterial {
    pub diffuse: Rgb,
    pub reflective: Rgb,
    pub roughness: f32,
    pub emitted: Rgb,
    pub alpha: f32,
    /// A `c` inside the block that another field follows.
    pub cutoff_deg: Option<f32>,
    pub textured: bool,
    /// Byte offset of its `material` token.
    pub offset: usize,
}

impl LegacyMaterial {
    /// Whether the material emits (its faces are lights).
    pub fn emits(&self) -> bool {
        self.emitted.max_element() > 0.0
    }
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

/// An `f` statement: four vertex indices (from 0) and the material active at it.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Face {
    pub vertices: [usize; 4],
    pub material: usize,
    /// The `c` statements written before the face (an index into
    /// [`Statements::cutoffs`]: the first `statements` of them).
    pub statements: usize,
    /// Byte offset of its `f` token.
    pub offset: usize,
}

/// A spotlight cutoff `c` read where a statement may stand.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Cutoff {
    pub value: f32,
    /// `Some` for a `c` that ends the fields of a material block: it could
    /// be that block's field or a statement for the faces that follow.
    pub trailing: Option<TrailingCutoff>,
}

/// A `c` right after the last field of material `material`'s block.
/// Newlines do not separate statements, so only the material tells the
/// two readings apart (phase 2, [`super::cutoffs`]).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TrailingCutoff {
    pub material: usize,
    /// Byte offset of the `c` token.
    pub offset: usize,
}

/// Block fields: names that continue an open `material` block.
fn is_block_field(token: &str) -> bool {
    matches!(
        token,
        "diffuse" | "texture_file" | "reflective" | "roughness" | "emitted" | "alpha"
    )
}

/// Phase 1: reads `source`'s statements; the first bad token is an error
/// naming its line and column.
pub(super) fn read(source: &SourceText) -> Result<Statements, SceneError> {
    let mut p = Parser::new(source);
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut materials: Vec<LegacyMaterial> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    let mut spheres: Vec<SphereStatement> = Vec::new();
    let mut active: Option<usize> = None;
    let mut open_block = false;
    let mut cutoffs: Vec<Cutoff> = Vec::new();
    let mut background = Rgb::ZERO;
    let mut camera: Option<CameraSpec> = None;

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
                    offset: tok.offset,
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
                spheres.push(SphereStatement {
                    sphere: Sphere { center, radius },
                    material,
                    offset: tok.offset,
                });
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

    Ok(Statements {
        vertices,
        materials,
        faces,
        spheres,
        cutoffs,
        background,
        camera,
    })
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
        aperture: Aperture::Pinhole,
    };
    spec.check().map_err(|m| p.error(Some(tok), m))?;
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_text(text: &str) -> Result<Statements, SceneError> {
        read(&SourceText::new("t.obj", text))
    }

    #[test]
    fn statements_are_read_in_file_order_with_their_offsets() {
        let s = read_text(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
             material diffuse 0.5 0.5 0.5 c 30 alpha 0.5\n\
             material emitted 1 1 1 c 20\n\
             m 1 f 1 2 3 4\nc 45\nm 0 s 0 0 1 0.5\nbackground_color 0 0 0\n",
        )
        .expect("valid");
        assert_eq!(s.vertices.len(), 4);
        assert_eq!(s.materials.len(), 2);
        // A `c` that another block field follows is the material's own.
        assert_eq!(s.materials[0].cutoff_deg, Some(30.0));
        assert_eq!(s.materials[0].alpha, 0.5);
        assert!(s.materials[1].emits());
        // A `c` that ends a block is left for phase 2; a `c` statement not.
        assert_eq!(s.cutoffs.len(), 2);
        let trailing = s.cutoffs[0].trailing.as_ref().expect("trailing");
        assert_eq!(trailing.material, 1);
        assert_eq!(s.cutoffs[0].value, 20.0);
        assert!(s.cutoffs[1].trailing.is_none());
        assert_eq!(s.faces.len(), 1);
        assert_eq!(s.faces[0].vertices, [0, 1, 2, 3]);
        assert_eq!(s.faces[0].material, 1);
        assert_eq!(s.faces[0].statements, 1);
        assert_eq!(s.faces[0].offset, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nmaterial diffuse 0.5 0.5 0.5 c 30 alpha 0.5\nmaterial emitted 1 1 1 c 20\nm 1 ".len());
        assert_eq!(s.spheres.len(), 1);
        assert_eq!(s.spheres[0].material, 0);
        assert!(s.camera.is_none());
    }

    #[test]
    fn a_bad_token_is_an_error_at_its_line_and_column() {
        let e = read_text("v 0 0 0\n  bogus 1\n").expect_err("an error");
        assert_eq!((e.line, e.column), (2, 3));
        assert!(e.message.contains("unknown token `bogus`"), "{}", e.message);
        let e = read_text("v 0 0 0\nf 1 2 3 4\n").expect_err("an error");
        assert_eq!((e.line, e.column), (2, 1));
        assert!(e.message.contains("active material"), "{}", e.message);
    }
}
