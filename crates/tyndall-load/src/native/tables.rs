//! The TOML tables of the native format, as serde reads them, and the
//! placing of parse errors at the offending key.

use crate::source::{SceneError, SourceText};
use serde::Deserialize;
use serde_spanned::Spanned;
use std::collections::BTreeMap;

pub(super) type V3 = [f32; 3];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    pub(super) camera: Spanned<CameraTable>,
    #[serde(default)]
    pub(super) render: Option<Spanned<RenderTable>>,
    #[serde(default)]
    pub(super) fog: Option<Spanned<FogTable>>,
    #[serde(default)]
    pub(super) materials: BTreeMap<String, Spanned<MaterialTable>>,
    #[serde(default)]
    pub(super) shapes: Vec<Spanned<ShapeTable>>,
    #[serde(default)]
    pub(super) lights: Vec<Spanned<LightTable>>,
    #[serde(default)]
    pub(super) media: Vec<Spanned<MediumTable>>,
    #[serde(default)]
    pub(super) include: Vec<Spanned<IncludeTable>>,
}

/// `[[include]]`: a scene file in another format (glTF), placed like a mesh.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct IncludeTable {
    pub(super) file: String,
    pub(super) translate: Option<V3>,
    pub(super) scale: Option<ColorValue>,
    pub(super) rotate_deg: Option<V3>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MediumTable {
    pub(super) sigma_t: ColorValue,
    pub(super) albedo: ColorValue,
    #[serde(default)]
    pub(super) g: f32,
    #[serde(rename = "box")]
    pub(super) bounds: Option<BoxTable>,
    pub(super) mesh: Option<MediumMesh>,
    pub(super) translate: Option<V3>,
    pub(super) scale: Option<ColorValue>,
    pub(super) rotate_deg: Option<V3>,
    pub(super) density: Option<String>,
    pub(super) file: Option<String>,
    pub(super) frequency: Option<f32>,
    pub(super) octaves: Option<u32>,
    pub(super) bias: Option<f32>,
    pub(super) seed: Option<u32>,
    pub(super) grid: Option<String>,
    pub(super) emission: Option<ColorValue>,
    pub(super) emission_grid: Option<String>,
    pub(super) temperature_grid: Option<String>,
    pub(super) temperature_scale: Option<f32>,
    pub(super) temperature_offset: Option<f32>,
    pub(super) blackbody_intensity: Option<f32>,
    pub(super) blackbody_law: Option<String>,
    pub(super) blackbody_tint: Option<ColorValue>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraTable {
    pub(super) position: V3,
    pub(super) look_at: V3,
    #[serde(default = "default_up")]
    pub(super) up: V3,
    pub(super) fov_y_deg: f32,
    pub(super) aperture_radius: Option<f32>,
    pub(super) focus_distance: Option<f32>,
}

pub(super) fn default_up() -> V3 {
    [0.0, 1.0, 0.0]
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RenderTable {
    pub(super) width: Option<u32>,
    pub(super) height: Option<u32>,
    pub(super) spp: Option<u32>,
    pub(super) seed: Option<u64>,
    pub(super) integrator: Option<String>,
    pub(super) step: Option<f32>,
    pub(super) volume_samples: Option<u32>,
    pub(super) interleave: Option<u32>,
    pub(super) max_depth: Option<u32>,
    pub(super) visibility: Option<String>,
    pub(super) shadow_map_resolution: Option<u32>,
    pub(super) max_bounces: Option<u32>,
    pub(super) exposure: Option<f32>,
    pub(super) output: Option<String>,
    pub(super) glass_model: Option<String>,
    pub(super) glass_opaque: Option<bool>,
    pub(super) light_sampling: Option<String>,
    pub(super) background: Option<ColorValue>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FogTable {
    pub(super) sigma_t: f32,
    pub(super) albedo: ColorValue,
    #[serde(default)]
    pub(super) g: f32,
    #[serde(rename = "box")]
    pub(super) bounds: Option<BoxTable>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BoxTable {
    pub(super) min: V3,
    pub(super) max: V3,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub(super) enum MaterialTable {
    Diffuse(DiffuseTable),
    Mirror(MirrorTable),
    Glossy(GlossyTable),
    Emissive(EmissiveTable),
    Glass(GlassTable),
    Dielectric(DielectricTable),
    Principled(PrincipledTable),
}

/// `type = "principled"`: glTF's metallic-roughness surface
/// ([`tyndall::materials::MetallicRoughness`]), optionally emitting.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PrincipledTable {
    pub(super) base_color: ColorValue,
    #[serde(default)]
    pub(super) metallic: f32,
    #[serde(default = "half")]
    pub(super) roughness: f32,
    pub(super) f0: Option<ColorValue>,
    pub(super) base_color_texture: Option<String>,
    pub(super) emission: Option<ColorValue>,
    #[serde(default)]
    pub(super) two_sided: bool,
    /// The clear coat's weight (Blender's Coat Weight, glTF's
    /// `clearcoatFactor`), 0 for none.
    #[serde(default)]
    pub(super) coat: f32,
    /// The coat's perceptual roughness.
    #[serde(default)]
    pub(super) coat_roughness: f32,
}

pub(super) fn half() -> f32 {
    0.5
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DielectricTable {
    pub(super) ior: f32,
    /// σa of the inside per scene unit (default clear).
    pub(super) absorption: Option<ColorValue>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DiffuseTable {
    pub(super) reflectance: ColorValue,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MirrorTable {
    pub(super) reflectance: ColorValue,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GlossyTable {
    pub(super) reflectance: ColorValue,
    pub(super) roughness: f32,
    #[serde(default)]
    pub(super) diffuse: Option<ColorValue>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EmissiveTable {
    pub(super) radiance: ColorValue,
    #[serde(default)]
    pub(super) two_sided: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GlassTable {
    pub(super) color: ColorValue,
    #[serde(default = "one")]
    pub(super) alpha: f32,
}

pub(super) fn one() -> f32 {
    1.0
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub(super) enum ShapeTable {
    Sphere(SphereTable),
    Quad(QuadTable),
    Box(BoxShapeTable),
    Mesh(MeshTable),
    Triangles(TrianglesTable),
}

/// A medium's `mesh` region: a Wavefront .obj file, or a closed mesh
/// given in the scene itself as flat arrays (as `triangles` shapes give
/// theirs), in world coordinates.
#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum MediumMesh {
    File(String),
    Inline(InlineMeshTable),
}

/// `mesh = { positions = [...], indices = [...] }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InlineMeshTable {
    pub(super) positions: NumberArray<f32>,
    pub(super) indices: NumberArray<u32>,
}

/// A flat array of numbers: written in the text, or `"@array:K"`, the
/// K-th array given beside the text ([`super::parse_with_arrays`]).
pub(super) enum NumberArray<T> {
    Inline(Vec<T>),
    Beside(String),
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for NumberArray<T> {
    /// A sequence or a string, each read as such, so a bad element is
    /// named as serde names it ("invalid type: string "x", expected f32").
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for Visitor<T> {
            type Value = NumberArray<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a flat array of numbers, or \"@array:K\" for an array given beside the text",
                )
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Self::Value, A::Error> {
                let mut values = Vec::with_capacity(seq.size_hint().unwrap_or(0));
                while let Some(v) = seq.next_element()? {
                    values.push(v);
                }
                Ok(NumberArray::Inline(values))
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<Self::Value, E> {
                Ok(NumberArray::Beside(name.to_owned()))
            }
        }
        deserializer.deserialize_any(Visitor(std::marker::PhantomData))
    }
}

/// `type = "triangles"`: a mesh given in the scene itself, as flat
/// arrays (three numbers a vertex, three indices a triangle).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TrianglesTable {
    pub(super) positions: NumberArray<f32>,
    pub(super) indices: NumberArray<u32>,
    #[serde(default)]
    pub(super) normals: Option<NumberArray<f32>>,
    #[serde(default)]
    pub(super) uvs: Option<NumberArray<f32>>,
    pub(super) material: String,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SphereTable {
    pub(super) center: V3,
    pub(super) radius: f32,
    pub(super) material: String,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct QuadTable {
    pub(super) corners: [V3; 4],
    pub(super) material: String,
    #[serde(default)]
    pub(super) one_sided: bool,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BoxShapeTable {
    pub(super) min: V3,
    pub(super) max: V3,
    pub(super) material: String,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshTable {
    pub(super) file: String,
    pub(super) material: String,
    #[serde(default)]
    pub(super) translate: Option<V3>,
    #[serde(default)]
    pub(super) scale: Option<ColorValue>,
    #[serde(default)]
    pub(super) rotate_deg: Option<V3>,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub(super) enum LightTable {
    Point(PointTable),
    Spot(SpotTable),
    Directional(DirectionalTable),
    Quad(QuadLightTable),
    Environment(EnvironmentTable),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PointTable {
    pub(super) position: V3,
    pub(super) intensity: Option<ColorValue>,
    pub(super) power: Option<ColorValue>,
    /// The nadir of an `ies` profile (default straight down).
    pub(super) direction: Option<V3>,
    pub(super) temperature_k: Option<f32>,
    pub(super) ies: Option<String>,
    pub(super) ies_rotate_deg: Option<f32>,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SpotTable {
    pub(super) position: V3,
    pub(super) direction: Option<V3>,
    pub(super) look_at: Option<V3>,
    pub(super) cutoff_deg: f32,
    #[serde(default)]
    pub(super) profile: Option<String>,
    pub(super) inner_deg: Option<f32>,
    pub(super) intensity: Option<ColorValue>,
    pub(super) temperature_k: Option<f32>,
    pub(super) ies: Option<String>,
    pub(super) ies_rotate_deg: Option<f32>,
    pub(super) gobo: Option<String>,
    pub(super) gobo_rotate_deg: Option<f32>,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DirectionalTable {
    pub(super) direction: V3,
    pub(super) irradiance: ColorValue,
    pub(super) temperature_k: Option<f32>,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EnvironmentTable {
    /// The uniform radiance, or the map's multiplier (default 1 with a map).
    pub(super) radiance: Option<ColorValue>,
    /// An equirectangular map (OpenEXR or Radiance HDR), relative to the scene.
    pub(super) map: Option<String>,
    /// The map's turn about +y (degrees).
    pub(super) map_rotate_deg: Option<f32>,
    pub(super) temperature_k: Option<f32>,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct QuadLightTable {
    pub(super) corners: [V3; 4],
    pub(super) radiance: ColorValue,
    #[serde(default)]
    pub(super) two_sided: bool,
    pub(super) temperature_k: Option<f32>,
    /// The light group the emitter is in (AOV `light_groups`).
    #[serde(default)]
    pub(super) light_group: Option<String>,
}

impl ShapeTable {
    /// The light group the shape's emitters are in, if named.
    pub(super) fn light_group(&self) -> Option<&str> {
        match self {
            ShapeTable::Sphere(t) => t.light_group.as_deref(),
            ShapeTable::Quad(t) => t.light_group.as_deref(),
            ShapeTable::Box(t) => t.light_group.as_deref(),
            ShapeTable::Mesh(t) => t.light_group.as_deref(),
            ShapeTable::Triangles(t) => t.light_group.as_deref(),
        }
    }
}

impl LightTable {
    /// The light group the light is in, if named.
    pub(super) fn light_group(&self) -> Option<&str> {
        match self {
            LightTable::Point(t) => t.light_group.as_deref(),
            LightTable::Spot(t) => t.light_group.as_deref(),
            LightTable::Directional(t) => t.light_group.as_deref(),
            LightTable::Quad(t) => t.light_group.as_deref(),
            LightTable::Environment(t) => t.light_group.as_deref(),
        }
    }
}

/// Re-parses the body of a `type`-tagged table as its variant's struct.
/// serde reports errors inside internally tagged enums at the table's
/// header only; parsed alone, the body gives toml's exact span.
pub(super) fn variant_error(section: &str, kind: &str, body: &str) -> Option<toml::de::Error> {
    fn check<T: serde::de::DeserializeOwned>(body: &str) -> Option<toml::de::Error> {
        toml::from_str::<T>(body).err()
    }
    match (section, kind) {
        ("materials", "diffuse") => check::<DiffuseTable>(body),
        ("materials", "mirror") => check::<MirrorTable>(body),
        ("materials", "glossy") => check::<GlossyTable>(body),
        ("materials", "emissive") => check::<EmissiveTable>(body),
        ("materials", "glass") => check::<GlassTable>(body),
        ("materials", "dielectric") => check::<DielectricTable>(body),
        ("materials", "principled") => check::<PrincipledTable>(body),
        ("shapes", "sphere") => check::<SphereTable>(body),
        ("shapes", "quad") => check::<QuadTable>(body),
        ("shapes", "box") => check::<BoxShapeTable>(body),
        ("shapes", "mesh") => check::<MeshTable>(body),
        ("shapes", "triangles") => check::<TrianglesTable>(body),
        ("lights", "point") => check::<PointTable>(body),
        ("lights", "spot") => check::<SpotTable>(body),
        ("lights", "directional") => check::<DirectionalTable>(body),
        ("lights", "quad") => check::<QuadLightTable>(body),
        ("lights", "environment") => check::<EnvironmentTable>(body),
        _ => None,
    }
}

/// The most precise location for a parse error at byte `offset`: inside
/// a tagged table, the offending key (see [`variant_error`]).
pub(super) fn locate_parse_error(source: &SourceText, offset: usize, message: &str) -> SceneError {
    let text = &source.text;
    let line_start = text[..offset.min(text.len())]
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let header = text[line_start..].lines().next().unwrap_or("").trim();
    let section = header
        .trim_matches(['[', ']'])
        .split('.')
        .next()
        .unwrap_or("");
    if header.starts_with('[') && matches!(section, "materials" | "shapes" | "lights") {
        let body = source.table_body(line_start);
        let mut blanked = text[body.clone()].to_string();
        let kind = toml::from_str::<toml::Table>(&blanked)
            .ok()
            .and_then(|t| t.get("type").and_then(|v| v.as_str()).map(str::to_owned));
        if let Some(kind) = kind {
            // Blank the `type = …` line, keeping every other offset.
            if let Some(at) = crate::source::find_key(&blanked, "type") {
                let end = blanked[at..].find('\n').map_or(blanked.len(), |i| at + i);
                blanked.replace_range(at..end, &" ".repeat(end - at));
            }
            if let Some(e) = variant_error(section, &kind, &blanked)
                && let Some(span) = e.span()
            {
                return source
                    .error_at(body.start + span.start, e.message().trim_end().to_string());
            }
        } else if message.contains("missing field `type`") || message.contains("unknown variant") {
            return source.error_at_key(body, "type", message.to_string());
        }
    }
    source.error_at(offset, message.to_string())
}

/// A colour written as one grey number or an `[r, g, b]` array.
#[derive(Clone, Copy, Debug)]
pub(super) struct ColorValue(pub(super) V3);

impl<'de> Deserialize<'de> for ColorValue {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = ColorValue;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an [r, g, b] array of numbers")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<ColorValue, E> {
                Ok(ColorValue([v as f32; 3]))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<ColorValue, E> {
                Ok(ColorValue([v as f32; 3]))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<ColorValue, E> {
                Ok(ColorValue([v as f32; 3]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<ColorValue, A::Error> {
                let mut c = [0.0f32; 3];
                for (i, slot) in c.iter_mut().enumerate() {
                    *slot = seq
                        .next_element()?
                        .ok_or_else(|| serde::de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<f32>()?.is_some() {
                    return Err(serde::de::Error::invalid_length(4, &self));
                }
                Ok(ColorValue(c))
            }
        }
        d.deserialize_any(Visitor)
    }
}
