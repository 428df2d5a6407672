//! The TOML scene-file format (documented key by key in `docs/SCENE_FORMAT.md`).
//!
//! Values are checked while they are read, so every error names the file, the line and column
//! of the offending value and what was expected.

use std::num::NonZeroU32;
use std::ops::Range;
use std::path::Path;

use glam::DVec3;
use serde::{Deserialize, Deserializer, de};
use thiserror::Error;
use toml::Spanned;

use super::lights::{Lights, PointLight};
use super::studio::{self, Studio};
use super::{SceneDescription, SceneObject};
use crate::cameras::PinholeCamera;
use crate::geometry::{
    Cylinder, Disc, GeometryError, Parallelogram, Plane, Shape, Sphere, TriangleMesh,
};
use crate::surfaces::{Chequerboard, Colour, Coloured, Mirror, Refractive, Surface, Transparent};

/// A scene file that could not be read or understood.
#[derive(Debug, Error)]
pub enum SceneFileError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}:{line}:{column}: {message}")]
    Invalid {
        path: String,
        line: usize,
        column: usize,
        message: String,
    },
}

/// 1-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset.min(text.len())).unwrap_or(text);
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.matches('\n').count() + 1;
    (line, before[line_start..].chars().count() + 1)
}

/// Largest magnitude of any length or coordinate: far beyond any scene's scale, and small enough
/// that products of a few such numbers (cross products, squared lengths) stay finite.
const MAX_MAGNITUDE: f64 = 1e15;

/// A finite number of magnitude at most [`MAX_MAGNITUDE`].
#[derive(Debug, Clone, Copy)]
struct Finite(f64);

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if x.abs() <= MAX_MAGNITUDE {
            Ok(Finite(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a finite number of magnitude at most {MAX_MAGNITUDE:e}, got {x}"
            )))
        }
    }
}

/// A positive number of at most [`MAX_MAGNITUDE`].
#[derive(Debug, Clone, Copy)]
struct Positive(f64);

impl<'de> Deserialize<'de> for Positive {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if x > 0.0 && x <= MAX_MAGNITUDE {
            Ok(Positive(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a positive number of at most {MAX_MAGNITUDE:e}, got {x}"
            )))
        }
    }
}

/// A fraction of light in [0, 1].
#[derive(Debug, Clone, Copy)]
struct Coefficient(f64);

impl<'de> Deserialize<'de> for Coefficient {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if (0.0..=1.0).contains(&x) {
            Ok(Coefficient(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a coefficient between 0 and 1, got {x}"
            )))
        }
    }
}

/// Three finite numbers: a point, a vector or an RGB colour.
#[derive(Debug, Clone, Copy)]
struct Vector(DVec3);

impl<'de> Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let [x, y, z] = <[Finite; 3]>::deserialize(d)?;
        Ok(Vector(DVec3::new(x.0, y.0, z.0)))
    }
}

/// A colour: three finite, non-negative numbers.
#[derive(Debug, Clone, Copy)]
struct Rgb(Colour);

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let c = Vector::deserialize(d)?.0;
        if c.min_element() < 0.0 {
            return Err(de::Error::custom(format!(
                "expected a colour with non-negative components, got {c}"
            )));
        }
        Ok(Rgb(c))
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    studio: Option<StudioName>,
    render: Option<Spanned<RenderSection>>,
    camera: Option<Spanned<CameraSection>>,
    #[serde(default)]
    light: Vec<LightSection>,
    #[serde(default)]
    object: Vec<ObjectSection>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "snake_case")]
enum StudioName {
    /// Sky, floor, lights and camera of TIM's standard studio.
    Empty,
    /// The empty studio plus TIM's cylinder lattice.
    Lattice,
    /// Nothing at all: no sky, no floor, no lights.
    None,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RenderSection {
    width: Option<NonZeroU32>,
    height: Option<NonZeroU32>,
    spp: Option<NonZeroU32>,
    seed: Option<u64>,
    max_trace_level: Option<NonZeroU32>,
    shadows: Option<bool>,
}

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum CameraSection {
    Pinhole {
        position: Vector,
        view_direction: Vector,
        up: Vector,
        horizontal_view_angle_deg: Positive,
    },
}

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum LightSection {
    Ambient {
        colour: Rgb,
    },
    Point {
        position: Vector,
        colour: Rgb,
        phong_exponent: Option<Positive>,
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectSection {
    name: Option<String>,
    #[serde(default = "yes")]
    shadow_throwing: bool,
    shape: Spanned<ShapeSection>,
    surface: SurfaceSection,
}

fn yes() -> bool {
    true
}

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum ShapeSection {
    Sphere {
        centre: Vector,
        radius: Positive,
    },
    Plane {
        point: Vector,
        normal: Vector,
        u_direction: Option<Vector>,
    },
    Disc {
        centre: Vector,
        normal: Vector,
        radius: Positive,
    },
    Cylinder {
        start: Vector,
        end: Vector,
        radius: Positive,
    },
    Parallelogram {
        corner: Vector,
        span_u: Vector,
        span_v: Vector,
    },
    TriangleMesh {
        vertices: Vec<Vector>,
        triangles: Vec<[u32; 3]>,
    },
}

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum SurfaceSection {
    Coloured {
        diffuse: Rgb,
        specular: Option<Rgb>,
    },
    Shiny {
        colour: Rgb,
    },
    Matt {
        colour: Rgb,
    },
    ConstantColour {
        colour: Rgb,
    },
    Chequerboard {
        tile_width: Option<Positive>,
        surfaces: Box<[SurfaceSection; 2]>,
    },
    Mirror {
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    Refractive {
        index_ratio: Positive,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    Transparent {
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
}

impl ShapeSection {
    fn build(self) -> Result<Shape, GeometryError> {
        Ok(match self {
            ShapeSection::Sphere { centre, radius } => {
                Shape::Sphere(Sphere::new(centre.0, radius.0)?)
            }
            ShapeSection::Plane {
                point,
                normal,
                u_direction,
            } => {
                let u = u_direction.map_or_else(|| normal.0.any_orthogonal_vector(), |u| u.0);
                Shape::Plane(Plane::new(point.0, normal.0, u)?)
            }
            ShapeSection::Disc {
                centre,
                normal,
                radius,
            } => Shape::Disc(Disc::new(centre.0, normal.0, radius.0)?),
            ShapeSection::Cylinder { start, end, radius } => {
                Shape::Cylinder(Cylinder::new(start.0, end.0, radius.0)?)
            }
            ShapeSection::Parallelogram {
                corner,
                span_u,
                span_v,
            } => Shape::Parallelogram(Parallelogram::new(corner.0, span_u.0, span_v.0)?),
            ShapeSection::TriangleMesh {
                vertices,
                triangles,
            } => Shape::TriangleMesh(TriangleMesh::new(
                vertices.into_iter().map(|v| v.0).collect(),
                triangles,
            )?),
        })
    }
}

impl SurfaceSection {
    fn build(self) -> Surface {
        match self {
            SurfaceSection::Coloured { diffuse, specular } => Surface::Coloured(Coloured {
                diffuse: diffuse.0,
                specular: specular.map_or(Colour::ZERO, |s| s.0),
            }),
            SurfaceSection::Shiny { colour } => Surface::Coloured(Coloured::shiny(colour.0)),
            SurfaceSection::Matt { colour } => Surface::Coloured(Coloured::matt(colour.0)),
            SurfaceSection::ConstantColour { colour } => Surface::ConstantColour(colour.0),
            SurfaceSection::Chequerboard {
                tile_width,
                surfaces,
            } => {
                let [a, b] = *surfaces;
                Surface::Chequerboard(Chequerboard {
                    tile_width: tile_width.map_or(1.0, |w| w.0),
                    surfaces: Box::new([a.build(), b.build()]),
                })
            }
            SurfaceSection::Mirror {
                reflection_coefficient,
            } => Surface::Mirror(Mirror {
                reflection_coefficient: reflection_coefficient.map_or(1.0, |c| c.0),
            }),
            SurfaceSection::Refractive {
                index_ratio,
                transmission_coefficient,
            } => Surface::Refractive(Refractive {
                index_ratio: index_ratio.0,
                transmission_coefficient: transmission_coefficient.map_or(1.0, |c| c.0),
            }),
            SurfaceSection::Transparent {
                transmission_coefficient,
            } => Surface::Transparent(Transparent {
                transmission_coefficient: transmission_coefficient.map_or(1.0, |c| c.0),
            }),
        }
    }
}

/// Reads a scene file.
pub fn load(path: &Path) -> Result<SceneDescription, SceneFileError> {
    let text = std::fs::read_to_string(path).map_err(|source| SceneFileError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse(&text, &path.display().to_string())
}

/// Parses scene-file text; `path` is only used in error messages.
pub fn parse(text: &str, path: &str) -> Result<SceneDescription, SceneFileError> {
    let invalid = |span: Option<Range<usize>>, message: String| {
        let (line, column) = line_column(text, span.map_or(0, |s| s.start));
        SceneFileError::Invalid {
            path: path.to_string(),
            line,
            column,
            message,
        }
    };
    let file: File =
        toml::from_str(text).map_err(|e| invalid(e.span(), e.message().trim().to_string()))?;

    let studio = match file.studio.unwrap_or(StudioName::Empty) {
        StudioName::Empty => Some(Studio::Empty),
        StudioName::Lattice => Some(Studio::Lattice),
        StudioName::None => None,
    };
    let mut scene = match studio {
        Some(s) => s.description(),
        None => SceneDescription {
            objects: Vec::new(),
            arrays: Vec::new(),
            lights: Lights::none(),
            camera: studio::camera(),
            render: Default::default(),
        },
    };

    if let Some(r) = file.render {
        let span = r.span();
        let r = r.into_inner();
        let s = &mut scene.render;
        s.width = r.width.map_or(s.width, NonZeroU32::get);
        s.height = r.height.map_or(s.height, NonZeroU32::get);
        s.spp = r.spp.map_or(s.spp, NonZeroU32::get);
        s.seed = r.seed.unwrap_or(s.seed);
        s.max_trace_level = r.max_trace_level.map_or(s.max_trace_level, NonZeroU32::get);
        s.shadows = r.shadows.unwrap_or(s.shadows);
        s.validate().map_err(|m| invalid(Some(span), m))?;
    }

    if let Some(camera) = file.camera {
        let span = camera.span();
        let CameraSection::Pinhole {
            position,
            view_direction,
            up,
            horizontal_view_angle_deg,
        } = camera.into_inner();
        if horizontal_view_angle_deg.0 >= 180.0 {
            return Err(invalid(
                Some(span),
                "horizontal_view_angle_deg must be below 180".into(),
            ));
        }
        scene.camera = PinholeCamera::new(
            position.0,
            view_direction.0,
            up.0,
            horizontal_view_angle_deg.0.to_radians(),
        )
        .ok_or_else(|| {
            invalid(
                Some(span),
                "camera view_direction and up must be non-zero and not parallel".into(),
            )
        })?;
    }

    // Lights given in the file replace the studio's lights.
    if !file.light.is_empty() {
        let mut lights = Lights::none();
        for light in file.light {
            match light {
                LightSection::Ambient { colour } => lights.ambient += colour.0,
                LightSection::Point {
                    position,
                    colour,
                    phong_exponent,
                } => lights.points.push(PointLight {
                    position: position.0,
                    colour: colour.0,
                    phong_exponent: phong_exponent.map_or(40.0, |k| k.0),
                }),
            }
        }
        scene.lights = lights;
    }

    for (i, object) in file.object.into_iter().enumerate() {
        let name = object.name.unwrap_or_else(|| format!("object {}", i + 1));
        let span = object.shape.span();
        let shape = object
            .shape
            .into_inner()
            .build()
            .map_err(|e| invalid(Some(span), format!("object '{name}': {e}")))?;
        scene.objects.push(SceneObject {
            name,
            shape,
            surface: object.surface.build(),
            shadow_throwing: object.shadow_throwing,
        });
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> String {
        parse(text, "s.toml").unwrap_err().to_string()
    }

    #[test]
    fn the_issue_example_parses() {
        let s = parse(
            r#"
studio = "lattice"
[render]
width = 64
height = 48
[camera]
type = "pinhole"
position = [0,0,0]
view_direction = [0,0,1]
up = [0,1,0]
horizontal_view_angle_deg = 20
[[light]]
type = "point"
position = [100,300,-500]
colour = [1,1,1]
[[object]]
name = "ball"
shadow_throwing = true
shape = { type = "sphere", centre = [0,0,5], radius = 0.5 }
surface = { type = "refractive", index_ratio = 1.5, transmission = 0.96 }
"#,
            "s.toml",
        )
        .unwrap();
        assert_eq!(s.objects.len(), 2 + 48 + 1);
        assert_eq!((s.render.width, s.render.height), (64, 48));
        assert_eq!(s.lights.points.len(), 1);
        assert_eq!(
            s.lights.ambient,
            Colour::ZERO,
            "file lights replace the studio's"
        );
        assert_eq!(
            s.objects.last().unwrap().surface,
            Surface::Refractive(Refractive {
                index_ratio: 1.5,
                transmission_coefficient: 0.96
            })
        );
    }

    #[test]
    fn errors_name_line_column_and_reason() {
        let e = error(
            "studio = \"empty\"\n[[object]]\nshape = { type = \"sphere\", centre = [0,0,5], radius = -0.5 }\nsurface = { type = \"matt\", colour = [1,1,1] }\n",
        );
        assert!(e.starts_with("s.toml:3:"), "{e}");
        assert!(
            e.contains("expected a positive number of at most 1e15, got -0.5"),
            "{e}"
        );

        let e = error("[render]\nwidht = 3\n");
        assert!(
            e.starts_with("s.toml:2:1:") && e.contains("unknown field `widht`"),
            "{e}"
        );

        let e = error("[render]\nwidth = \n");
        assert!(e.starts_with("s.toml:2:"), "{e}");

        let e = error(
            "[[object]]\nshape = { type = \"cylinder\", start = [0,0,1], end = [0,0,1], radius = 1 }\nsurface = { type = \"mirror\" }\n",
        );
        assert!(
            e.starts_with("s.toml:2:9:") && e.contains("start and end coincide"),
            "{e}"
        );

        let e = error(
            "[camera]\ntype = \"pinhole\"\nposition = [0,0,0]\nview_direction = [0,1,0]\nup = [0,2,0]\nhorizontal_view_angle_deg = 20\n",
        );
        assert!(e.contains("not parallel"), "{e}");

        let e = error(
            "[[object]]\nshape = { type = \"sphere\", centre = [0,nan,5], radius = 1 }\nsurface = { type = \"mirror\" }\n",
        );
        assert!(e.contains("finite"), "{e}");
    }

    #[test]
    fn a_plane_u_direction_along_the_normal_is_rejected() {
        let e = error(
            "[[object]]\nshape = { type = \"plane\", point = [0,0,5], normal = [0,0,1], u_direction = [0,0,2] }\nsurface = { type = \"mirror\" }\n",
        );
        assert!(
            e.starts_with("s.toml:2:9:") && e.contains("parallel to the normal"),
            "{e}"
        );
    }

    #[test]
    fn line_and_column_are_one_based() {
        assert_eq!(line_column("ab\ncd", 0), (1, 1));
        assert_eq!(line_column("ab\ncd", 4), (2, 2));
    }
}
