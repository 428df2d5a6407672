//! Where objects go: `[[object]]`, `[[device]]`, `[[group]]` and `[[include]]` entries, each
//! with an optional
//! `transform` (scale, then rotate, then translate) and `array` (copies on a 1-, 2- or 3-D
//! grid).
//!
//! A group's transform applies to its members (after their own); an array repeats the
//! transformed object or group along vectors given in the enclosing frame. Arrays of arrays
//! flatten into one array whose offsets are all the sums, so Embree needs only one level of
//! instancing.

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3};
use serde::{Deserialize, Deserializer, de};

use super::confine::Within;
use super::parts::Spanned;
use super::{SceneFileError, Source};
use crate::devices::{AidKeys, CoordinateSystem, Edges, LensDevice, LensesKeys, Part};
use crate::geometry::{ObjectArray, Shape, ShapeKeys, Transform, TransformKeys};
use crate::keys::{Array, Finite, Positive, Vector};
use crate::math::ReferenceFrame;
use crate::picture::Picture;
use crate::scene::{SceneObject, SeenBy};
use crate::surfaces::{Surface, SurfaceKeys, mesh_materials};

/// Most array copies a scene may have in all (after flattening nested arrays): each is an
/// Embree instance of about 500 bytes.
pub const MAX_ARRAY_ELEMENTS: u64 = 10_000_000;

/// Whether `shape` is a mesh with vertex colours of its own.
fn has_colours(shape: &Shape) -> bool {
    matches!(shape, Shape::TriangleMesh(m) if m.colours().is_some())
}

/// Largest MTL material library read, in bytes.
const MAX_LIBRARY_BYTES: u64 = 64 << 20;

/// Most objects a scene may have (each mesh file part is one; repetition belongs in arrays).
pub const MAX_OBJECTS: usize = 1_000_000;

/// Largest number of includes in a scene, counting each time a file is included (so that a
/// "diamond" of files including each other twice is refused at once, not after expanding
/// millions of copies).
pub const MAX_INCLUDES: usize = 10_000;

/// Most bytes of scene-file text a scene may have, with its includes (each time they are
/// included): 1 GiB, so that parsing them all takes a minute at most.
pub const MAX_SCENE_BYTES: usize = 1 << 30;

/// Deepest chain of files including each other (each level takes stack space while it is read).
pub const MAX_INCLUDE_DEPTH: usize = 100;

/// The error for a scene of more than [`MAX_OBJECTS`] objects.
pub(super) fn too_many_objects() -> String {
    format!("the scene has more than {MAX_OBJECTS} objects (repeated objects belong in arrays)")
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ObjectSection {
    name: Option<String>,
    #[serde(default = "super::yes")]
    shadow_throwing: bool,
    frame: Option<FrameName>,
    seen_by: Option<Spanned<SeenBy>>,
    shape: Spanned<ShapeKeys>,
    /// Omitted for a mesh file whose parts all have materials.
    surface: Option<Spanned<SurfaceKeys>>,
    transform: Option<Spanned<TransformKeys>>,
    array: Option<Spanned<ArraySection>>,
    surface_axes: Option<Spanned<SurfaceAxesSection>>,
}

/// Arrows along the surface-coordinate axes û, v̂ and the outward normal at a point of an
/// object's surface (the paper's §4.4 footnote).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SurfaceAxesSection {
    coordinates: Array<Finite, 2>,
    length: Option<Positive>,
    shaft_radius: Option<Positive>,
}

impl SurfaceAxesSection {
    /// The arrows at the point of `shape` (in world coordinates) with these coordinates.
    fn parts(&self, shape: &Shape) -> Result<Vec<Part>, String> {
        let [u, v] = self.coordinates.0.map(|c| c.0);
        let p = shape.point_at(DVec2::new(u, v)).ok_or_else(|| {
            format!(
                "surface_axes: the {} has no point with surface coordinates ({u}, {v}) \
                 (meshes and shapes of several parts have none to look up)",
                shape.kind()
            )
        })?;
        let f = shape.frame(p, 0);
        let length = self.length.map_or(0.5, |l| l.0);
        CoordinateSystem {
            origin: p,
            axes: [f.u, f.v, f.w],
            names: ["u axis", "v axis", "normal"],
            length,
            shaft_radius: self.shaft_radius.map_or(0.05 * length, |r| r.0),
            tip_length: 0.2 * length,
        }
        .parts()
        .map_err(|e| format!("surface_axes: {e}"))
    }
}

/// A `[[device]]` entry: a device of ideal thin lenses (`lenses`) or a visual aid (`aid`), each
/// expanding into one scene object per part.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DeviceSection {
    name: Option<String>,
    /// Whether the lenses throw shadows (edges always do); where not given, the device's
    /// own default (Dr TIM's), [`LensDevice::shadow_throwing`].
    shadow_throwing: Option<bool>,
    frame: Option<FrameName>,
    seen_by: Option<Spanned<SeenBy>>,
    transform: Option<Spanned<TransformKeys>>,
    array: Option<Spanned<ArraySection>>,
    lenses: Option<Spanned<LensesKeys>>,
    aid: Option<Spanned<AidKeys>>,
    /// Where not given, the device's own defaults (Dr TIM's), [`LensDevice::edge_defaults`].
    show_edges: Option<bool>,
    edge_radius: Option<Positive>,
    edge_surface: Option<Spanned<SurfaceKeys>>,
}

impl DeviceSection {
    /// Where the device's `lenses` or `aid` table is, for errors about the whole device.
    fn span(&self) -> Option<Range<usize>> {
        let aid = self.aid.as_ref().map(Spanned::span);
        self.lenses.as_ref().map(Spanned::span).or(aid)
    }

    /// The device's parts, or the span of the table at fault and what is wrong (`table`: the
    /// device's whole table).
    fn parts(&mut self, table: Range<usize>) -> Result<Vec<Part>, (Range<usize>, String)> {
        let lenses = match (self.lenses.take(), self.aid.take()) {
            (Some(lenses), None) => lenses,
            (None, Some(aid)) => {
                if self.show_edges == Some(true)
                    || self.edge_radius.is_some()
                    || self.edge_surface.is_some()
                {
                    return Err((
                        aid.span(),
                        "edges (show_edges, edge_radius, edge_surface) belong to lens devices, \
                         not to visual aids"
                            .into(),
                    ));
                }
                let span = aid.span();
                return aid.into_inner().build().map_err(|e| (span, e));
            }
            _ => {
                return Err((
                    table,
                    "a device needs exactly one of a `lenses` table (a device of lenses) and an \
                     `aid` table (a visual aid)"
                        .into(),
                ));
            }
        };
        let span = lenses.span();
        let lenses = lenses.into_inner();
        let kind = lenses.kind();
        let device = lenses
            .build()
            .map_err(|e| (span.clone(), format!("{kind}: {e}")))?;
        let edges = self.edges(device.as_ref())?;
        self.shadow_throwing.get_or_insert(device.shadow_throwing());
        device
            .parts(edges.as_ref())
            .map_err(|e| (span, format!("{kind}: {e}")))
    }

    /// The device's edges, if they are shown: as the entry says, or the device's defaults.
    fn edges(&mut self, device: &dyn LensDevice) -> Result<Option<Edges>, (Range<usize>, String)> {
        let defaults = device.edge_defaults();
        if !self.show_edges.unwrap_or(defaults.shown) {
            return Ok(None);
        }
        let surface = match self.edge_surface.take() {
            Some(s) => {
                let span = s.span();
                if s.get_ref().destination().is_some() {
                    return Err((span, "edge_surface cannot be a teleporting surface".into()));
                }
                s.into_inner().build().map_err(|e| (span, e))?
            }
            None => defaults.surface(),
        };
        Ok(Some(Edges {
            radius: self.edge_radius.as_ref().map_or(defaults.radius, |r| r.0),
            surface,
        }))
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GroupSection {
    name: Option<String>,
    frame: Option<FrameName>,
    seen_by: Option<Spanned<SeenBy>>,
    transform: Option<Spanned<TransformKeys>>,
    array: Option<Spanned<ArraySection>>,
    #[serde(default)]
    object: Vec<ObjectSection>,
    #[serde(default)]
    device: Vec<Spanned<DeviceSection>>,
    #[serde(default)]
    group: Vec<GroupSection>,
    #[serde(default)]
    include: Vec<IncludeSection>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct IncludeSection {
    file: Spanned<String>,
    name: Option<String>,
    frame: Option<FrameName>,
    seen_by: Option<Spanned<SeenBy>>,
    transform: Option<Spanned<TransformKeys>>,
    array: Option<Spanned<ArraySection>>,
}

/// The frame an object, group or include is at rest in; members inherit their group's.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum FrameName {
    Scene,
    Camera,
}

impl FrameName {
    fn or(frame: Option<FrameName>, inherited: ReferenceFrame) -> ReferenceFrame {
        match frame {
            None => inherited,
            Some(FrameName::Scene) => ReferenceFrame::Scene,
            Some(FrameName::Camera) => ReferenceFrame::Camera,
        }
    }
}

/// The frame an entry's objects are at rest in and the rays that meet them (`seen_by`), as its
/// group or include gives them; an entry may say otherwise for itself and its members.
#[derive(Debug, Clone, Copy)]
pub(super) struct Inherited {
    pub frame: ReferenceFrame,
    pub seen_by: SeenBy,
}

impl Inherited {
    /// The scene file's own entries: at rest in the scene, met by every ray.
    pub const TOP: Inherited = Inherited {
        frame: ReferenceFrame::Scene,
        seen_by: SeenBy::All,
    };

    /// The entry's own, refused (at its `seen_by`, else at `at`) where no ray could meet its
    /// objects: trajectories trace the scene frame only.
    fn within(
        self,
        source: &Source,
        frame: Option<FrameName>,
        seen_by: &Option<Spanned<SeenBy>>,
        at: Option<Range<usize>>,
    ) -> Result<Inherited, SceneFileError> {
        let own = Inherited {
            frame: FrameName::or(frame, self.frame),
            seen_by: seen_by.as_ref().map_or(self.seen_by, |s| *s.get_ref()),
        };
        match (own.frame, own.seen_by) {
            (ReferenceFrame::Camera, SeenBy::Trajectories) => Err(source.error(
                seen_by.as_ref().map(Spanned::span).or(at),
                "objects moving with the camera (frame = \"camera\") are never met by the ray \
                 trajectories, which trace the scene frame only, so seen_by = \"trajectories\" \
                 would hide them from every ray"
                    .into(),
            )),
            _ => Ok(own),
        }
    }
}

/// The placeable entries of a file or group.
#[derive(Debug, Default)]
pub(super) struct Items {
    pub object: Vec<ObjectSection>,
    pub device: Vec<Spanned<DeviceSection>>,
    pub group: Vec<GroupSection>,
    pub include: Vec<IncludeSection>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ArraySection {
    vectors: Vec<Vector>,
    counts: Vec<Count>,
    #[serde(default)]
    centred: bool,
}

/// A number of copies: a positive whole number.
#[derive(Debug, Clone, Copy)]
struct Count(u64);

impl<'de> Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let n = i64::deserialize(d)?;
        if n >= 1 && n as u64 <= MAX_ARRAY_ELEMENTS {
            Ok(Count(n as u64))
        } else {
            Err(de::Error::custom(format!(
                "expected a number of copies from 1 to {MAX_ARRAY_ELEMENTS}, got {n}"
            )))
        }
    }
}

/// Objects with their arrays (ranges into `objects`).
#[derive(Debug, Default)]
pub(super) struct Placed {
    pub objects: Vec<SceneObject>,
    pub arrays: Vec<ObjectArray>,
}

impl Placed {
    fn append(&mut self, other: Placed) {
        let shift = self.objects.len();
        self.objects.extend(other.objects);
        self.arrays
            .extend(other.arrays.into_iter().map(|a| ObjectArray {
                objects: a.objects.start + shift..a.objects.end + shift,
                offsets: a.offsets,
            }));
    }

    /// Array copies in all.
    fn copies(&self) -> u64 {
        self.arrays.iter().map(|a| a.offsets.len() as u64).sum()
    }

    /// Checks the scene-wide limits on objects and array copies.
    fn check_size(&self) -> Result<(), String> {
        if self.objects.len() > MAX_OBJECTS {
            return Err(too_many_objects());
        }
        let copies = self.copies();
        if copies > MAX_ARRAY_ELEMENTS {
            return Err(format!(
                "the scene's arrays have {copies} copies in all; at most {MAX_ARRAY_ELEMENTS} are supported"
            ));
        }
        Ok(())
    }

    /// Every object repeated at each of `offsets`: objects in no array become one new array;
    /// an existing array's copies are repeated (its offsets become all the sums).
    fn repeat(self, offsets: &[DVec3]) -> Result<Placed, String> {
        // Copies share their surfaces, so every copy of a device's teleporting surface would
        // send rays to the first copy's destination.
        if let Some(o) = self
            .objects
            .iter()
            .find(|o| matches!(&o.surface, Surface::Teleporting(t) if t.destination.is_some()))
        {
            return Err(format!(
                "'{}' teleports to another part of its device, which an array cannot repeat \
                 (every copy would teleport to the first copy's); give each copy as a device \
                 of its own",
                o.name
            ));
        }
        let mut in_array = vec![false; self.objects.len()];
        for a in &self.arrays {
            in_array[a.objects.clone()].fill(true);
        }
        // Afterwards the objects in no array are one array of offsets.len() copies, and each
        // array has offsets.len() times as many copies as before.
        let new_array = in_array.contains(&false) as u64;
        let total = (self.copies() + new_array) as u128 * offsets.len() as u128;
        if total > MAX_ARRAY_ELEMENTS as u128 {
            return Err(format!(
                "the scene's arrays would have {total} copies in all; at most {MAX_ARRAY_ELEMENTS} are supported"
            ));
        }
        let mut slots: Vec<Option<SceneObject>> = self.objects.into_iter().map(Some).collect();
        let mut take = |range: Range<usize>| -> Vec<SceneObject> {
            slots[range].iter_mut().filter_map(Option::take).collect()
        };
        let mut out = Placed::default();
        let plain: Vec<SceneObject> = (0..in_array.len())
            .filter(|&i| !in_array[i])
            .flat_map(|i| take(i..i + 1))
            .collect();
        if !plain.is_empty() {
            out.arrays.push(ObjectArray {
                objects: 0..plain.len(),
                offsets: offsets.to_vec(),
            });
            out.objects = plain;
        }
        for a in self.arrays {
            let start = out.objects.len();
            out.objects.extend(take(a.objects));
            out.arrays.push(ObjectArray {
                objects: start..out.objects.len(),
                offsets: offsets
                    .iter()
                    .flat_map(|o| a.offsets.iter().map(move |e| *e + *o))
                    .collect(),
            });
        }
        Ok(out)
    }
}

/// An entry's array: its span in the file and the world offsets of its copies.
type Copies = (Range<usize>, Vec<DVec3>);

/// Places the items of scene files, following includes.
pub(super) struct Placer<'a> {
    /// The files being included, outermost first (to detect cycles).
    stack: Vec<PathBuf>,
    /// Where the files named by the file being read must be, if they are confined.
    within: Option<&'a Within<'a>>,
    /// Objects placed so far (numbers unnamed objects).
    count: usize,
    /// Files included so far (each time they are included).
    includes: usize,
    /// Bytes of scene-file text so far (each time a file is included), counted from the files'
    /// sizes as soon as the includes naming them are read, before their text is.
    bytes: usize,
    /// Teleporting surfaces, to be linked to their destinations once every object is placed.
    pub(super) links: Vec<Link>,
    /// The picture files read so far, by their canonical paths.
    pictures: HashMap<PathBuf, Picture>,
    /// Warnings about the files read (unsupported MTL keys), each naming its object.
    pub(super) warnings: Vec<String>,
}

/// A teleporting object (its name; it may have named parts) and the name of its destination,
/// with the place in its file where the link is given, for errors.
pub(super) struct Link {
    pub origin: String,
    pub destination: String,
    pub at: SceneFileError,
}

impl<'a> Placer<'a> {
    /// A placer for the scene file at `top`, of `bytes` bytes, whose files are confined
    /// `within` that, if given.
    pub(super) fn new(top: &Path, bytes: usize, within: Option<&'a Within<'a>>) -> Placer<'a> {
        Placer {
            stack: vec![top.canonicalize().unwrap_or_else(|_| top.to_path_buf())],
            within,
            count: 0,
            includes: 0,
            bytes,
            links: Vec::new(),
            pictures: HashMap::new(),
            warnings: Vec::new(),
        }
    }

    /// Places `items` of the file `source` under the map `parent`, in the frame and seen by
    /// the rays `inherited` says unless they say otherwise; names get `prefix`.
    pub(super) fn items(
        &mut self,
        source: &Source,
        items: Items,
        parent: &Transform,
        inherited: Inherited,
        prefix: &str,
    ) -> Result<Placed, SceneFileError> {
        // The included files are admitted first, then counted from their sizes before any is
        // read, so that a scene of too many bytes is refused at once; a file that grows before
        // it is read adds the difference. A file that cannot be read counts 0 here; reading it
        // reports why.
        let admitted = items
            .include
            .iter()
            .map(|i| {
                self.admit(source, i.file.get_ref())
                    .map_err(|e| source.error(Some(i.file.span()), format!("include: {e}")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let sizes: Vec<usize> = admitted
            .iter()
            .map(|(path, _)| {
                std::fs::metadata(path).map_or(0, |m| m.len().try_into().unwrap_or(usize::MAX))
            })
            .collect();
        for (i, &size) in items.include.iter().zip(&sizes) {
            self.count_bytes(source, i.file.span(), size)?;
        }
        let mut placed = Placed::default();
        for o in items.object {
            let span = o.shape.span();
            placed.append(self.object(source, o, parent, inherited, prefix)?);
            placed
                .check_size()
                .map_err(|e| source.error(Some(span), e))?;
        }
        for d in items.device {
            let span = d.span();
            placed.append(self.device(source, d, parent, inherited, prefix)?);
            placed
                .check_size()
                .map_err(|e| source.error(Some(span), e))?;
        }
        for g in items.group {
            let name = join(prefix, g.name.as_deref());
            let (own, offsets) = self.placement(source, g.transform, g.array, parent, &name)?;
            let members = Items {
                object: g.object,
                device: g.device,
                group: g.group,
                include: g.include,
            };
            let inner = self.items(
                source,
                members,
                &own,
                inherited.within(source, g.frame, &g.seen_by, None)?,
                &name,
            )?;
            placed.append(self.repeat(source, inner, offsets, &name)?);
            placed.check_size().map_err(|e| source.error(None, e))?;
        }
        for ((i, size), (path, within)) in items.include.into_iter().zip(sizes).zip(admitted) {
            let name = join(prefix, i.name.as_deref());
            let (own, offsets) = self.placement(source, i.transform, i.array, parent, &name)?;
            let span = i.file.span();
            let key = path.canonicalize().unwrap_or_else(|_| path.clone());
            if self.stack.contains(&key) {
                let chain: Vec<String> = self
                    .stack
                    .iter()
                    .chain([&key])
                    .map(|p| p.display().to_string())
                    .collect();
                return Err(
                    source.error(Some(span), format!("include cycle: {}", chain.join(" -> ")))
                );
            }
            if self.stack.len() > MAX_INCLUDE_DEPTH {
                return Err(source.error(
                    Some(span),
                    format!("includes are nested more than {MAX_INCLUDE_DEPTH} levels deep"),
                ));
            }
            self.includes += 1;
            if self.includes > MAX_INCLUDES {
                return Err(source.error(
                    Some(span),
                    format!(
                        "the scene includes files more than {MAX_INCLUDES} times in all (a file \
                         included twice counts twice; repeated objects belong in arrays)"
                    ),
                ));
            }
            let (included, file) = super::read(&path, &[])
                .map_err(|e| source.error(Some(span.clone()), format!("include: {e}")))?;
            self.count_bytes(
                source,
                span.clone(),
                included.text.len().saturating_sub(size),
            )?;
            self.stack.push(key);
            let outer = std::mem::replace(&mut self.within, within);
            let inner = self.items(
                &included,
                file.items(),
                &own,
                inherited.within(source, i.frame, &i.seen_by, Some(span.clone()))?,
                &name,
            )?;
            self.within = outer;
            self.stack.pop();
            placed.append(self.repeat(source, inner, offsets, &name)?);
            placed
                .check_size()
                .map_err(|e| source.error(Some(span.clone()), e))?;
        }
        Ok(placed)
    }

    /// The path of the file `name` given in `source`, refused before it is touched where the
    /// files are confined and it is outside; with the confinement of the files it names in
    /// turn (none for a file the user named in the scene text itself).
    fn admit(
        &self,
        source: &Source,
        name: &str,
    ) -> Result<(PathBuf, Option<&'a Within<'a>>), String> {
        let path = source.dir().join(name);
        match self.within {
            Some(within) if !(self.stack.len() == 1 && within.trusts(name)) => {
                within.check(name, &path)?;
                Ok((path, Some(within)))
            }
            _ => Ok((path, None)),
        }
    }

    /// The picture file `name` given in `source`, admitted as any file it names is, and read
    /// once however often the scene names it.
    pub(super) fn picture(&mut self, source: &Source, name: &str) -> Result<Picture, String> {
        let (path, _) = self.admit(source, name)?;
        let key = path.canonicalize().unwrap_or_else(|_| path.clone());
        if let Some(picture) = self.pictures.get(&key) {
            return Ok(picture.clone());
        }
        let picture = Picture::load(&path).map_err(|e| e.to_string())?;
        self.pictures.insert(key, picture.clone());
        Ok(picture)
    }

    /// Opens the picture files the surface `keys` of `source` name.
    pub(super) fn open_pictures(
        &mut self,
        source: &Source,
        keys: &mut SurfaceKeys,
    ) -> Result<(), String> {
        for file in keys.pictures() {
            file.picture = Some(self.picture(source, &file.name)?);
        }
        Ok(())
    }

    /// Adds `bytes` of scene-file text, included at `span` of `source`, to the scene's total.
    fn count_bytes(
        &mut self,
        source: &Source,
        span: Range<usize>,
        bytes: usize,
    ) -> Result<(), SceneFileError> {
        self.bytes = self.bytes.saturating_add(bytes);
        if self.bytes > MAX_SCENE_BYTES {
            return Err(source.error(
                Some(span),
                format!(
                    "the scene's files come to more than {} MiB in all (a file included twice \
                     counts twice)",
                    MAX_SCENE_BYTES >> 20
                ),
            ));
        }
        Ok(())
    }

    fn object(
        &mut self,
        source: &Source,
        o: ObjectSection,
        parent: &Transform,
        inherited: Inherited,
        prefix: &str,
    ) -> Result<Placed, SceneFileError> {
        self.count += 1;
        let own_name = o.name.unwrap_or_else(|| format!("object {}", self.count));
        let rest = inherited.within(source, o.frame, &o.seen_by, Some(o.shape.span()))?;
        let name = join(prefix, Some(&own_name));
        let transform_span = o.transform.as_ref().map(Spanned::span);
        let (own, offsets) = self.placement(source, o.transform, o.array, parent, &name)?;
        let shape_span = o.shape.span();
        let label = super::object_label(&name);
        let at_shape = |e: String| source.error(Some(shape_span.clone()), format!("{label}: {e}"));
        // Files a mesh file names (MTL libraries, their textures) are relative to it, and
        // admitted as if the scene file named them.
        let mesh_dir = match o.shape.get_ref() {
            ShapeKeys::Mesh(mesh) => Path::new(mesh.file())
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default(),
            _ => PathBuf::new(),
        };
        let parts = match o.shape.into_inner() {
            ShapeKeys::Mesh(mesh) => {
                self.admit(source, mesh.file()).map_err(&at_shape)?;
                let mut open = |library: &str| {
                    let relative = mesh_dir.join(library);
                    let (path, _) = self.admit(source, &relative.to_string_lossy())?;
                    crate::files::read_regular(&path, MAX_LIBRARY_BYTES)
                        .map_err(|e| format!("{}: {e}", path.display()))
                };
                let (parts, warnings) = mesh
                    .load_with(source.dir(), o.surface.is_none().then_some(&mut open as _))
                    .map_err(&at_shape)?;
                self.warnings
                    .extend(warnings.into_iter().map(|w| format!("{label}: {w}")));
                parts
            }
            shape => shape
                .parts(source.dir())
                .map_err(&at_shape)?
                .into_iter()
                .map(|(part, shape)| (part, shape, None))
                .collect(),
        };
        // Each part's surface: the one given, or its material's.
        let (surface_span, given) = match o.surface {
            Some(s) => (s.span(), Some(s.into_inner())),
            None => (shape_span.clone(), None),
        };
        let at_surface =
            |e: String| source.error(Some(surface_span.clone()), format!("{label}: {e}"));
        let surface = match given {
            Some(mut keys) => {
                if let Some(destination) = keys.destination() {
                    self.links.push(Link {
                        origin: name.clone(),
                        destination: destination.to_string(),
                        at: source.error(Some(surface_span.clone()), String::new()),
                    });
                }
                self.open_pictures(source, &mut keys).map_err(&at_surface)?;
                Some(keys.build().map_err(&at_surface)?)
            }
            None => None,
        };
        let parts = parts
            .into_iter()
            .map(|(part, shape, material)| {
                let surface = match (&surface, material) {
                    (Some(s), _) => s.clone(),
                    (None, Some(m)) => {
                        let texture = match &m.diffuse_map {
                            Some(map) => {
                                let relative = mesh_dir.join(map);
                                let picture = self
                                    .picture(source, &relative.to_string_lossy())
                                    .map_err(|e| {
                                        at_shape(format!(
                                            "material '{}': map_Kd '{map}': {e}",
                                            m.name
                                        ))
                                    })?;
                                Some(picture)
                            }
                            None => None,
                        };
                        mesh_materials::from_material(&m, texture)
                    }
                    (None, None) if has_colours(&shape) => {
                        Surface::VertexColours(mesh_materials::VertexColours)
                    }
                    (None, None) => {
                        return Err(at_shape(if part.is_empty() {
                            "missing field `surface` (only a mesh file with materials or vertex \
                             colours may omit it)"
                                .into()
                        } else {
                            format!(
                                "missing field `surface`: mesh part '{part}' has no material \
                                 (usemtl) to show"
                            )
                        }));
                    }
                };
                Ok((part, shape, surface))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut placed = Placed::default();
        for (part, shape, surface) in parts {
            surface.check_shape(&shape).map_err(|e| {
                source.error(
                    Some(surface_span.clone()),
                    format!("{}: {e}", super::object_label(&name)),
                )
            })?;
            placed.objects.push(place(
                source,
                &own,
                PartSpans {
                    transform: transform_span.clone(),
                    shape: shape_span.clone(),
                    surface: surface_span.clone(),
                },
                SceneObject {
                    name: if part.is_empty() {
                        name.clone()
                    } else {
                        format!("{name}/{part}")
                    },
                    shape,
                    surface,
                    shadow_throwing: o.shadow_throwing,
                    frame: rest.frame,
                    seen_by: rest.seen_by,
                },
            )?);
        }
        if let Some(axes) = o.surface_axes {
            let at = axes.span();
            let parts = match placed.objects.as_slice() {
                [on] => axes.get_ref().parts(&on.shape),
                all => Err(format!(
                    "surface_axes: the mesh file has {} parts, and meshes have no surface \
                     coordinates to look up",
                    all.len()
                )),
            };
            let parts = parts.map_err(|e| {
                source.error(Some(at), format!("{}: {e}", super::object_label(&name)))
            })?;
            placed
                .objects
                .extend(parts.into_iter().map(|p| SceneObject {
                    name: format!("{name}/{}", p.name),
                    shape: p.shape,
                    surface: p.surface,
                    shadow_throwing: true,
                    frame: rest.frame,
                    seen_by: rest.seen_by,
                }));
        }
        self.repeat(source, placed, offsets, &name)
    }

    /// A device's parts as objects `NAME/part`, placed like an object's parts.
    fn device(
        &mut self,
        source: &Source,
        d: Spanned<DeviceSection>,
        parent: &Transform,
        inherited: Inherited,
        prefix: &str,
    ) -> Result<Placed, SceneFileError> {
        self.count += 1;
        let table = d.span();
        let mut d = d.into_inner();
        let own_name = d
            .name
            .take()
            .unwrap_or_else(|| format!("device {}", self.count));
        let rest = inherited.within(source, d.frame, &d.seen_by, Some(table.clone()))?;
        let name = join(prefix, Some(&own_name));
        let span = d.span().unwrap_or(table.clone());
        let transform_span = d.transform.as_ref().map(Spanned::span);
        let parts = d
            .parts(table)
            .map_err(|(at, e)| source.error(Some(at), format!("device '{name}': {e}")))?;
        let (own, offsets) =
            self.placement(source, d.transform.take(), d.array.take(), parent, &name)?;
        // A phase hologram's phase is in lengths of the scene, not of its shape: a device's lens
        // holograms would keep their focal lengths and centres while the device is scaled.
        let scaled = own.uniform_scale().is_none_or(|k| (k - 1.0).abs() > 1e-12);
        if scaled
            && parts
                .iter()
                .any(|p| matches!(p.surface, Surface::PhaseHologram(_)))
        {
            return Err(source.error(
                transform_span.or(Some(span)),
                format!(
                    "device '{name}': its lens holograms cannot be scaled (a phase hologram's \
                     phase is given in lengths of the scene); give the device's lengths instead"
                ),
            ));
        }
        let mut placed = Placed::default();
        for p in parts {
            placed.objects.push(place(
                source,
                &own,
                PartSpans {
                    transform: transform_span.clone(),
                    shape: span.clone(),
                    surface: span.clone(),
                },
                SceneObject {
                    name: format!("{name}/{}", p.name),
                    shape: p.shape,
                    surface: p.surface,
                    shadow_throwing: p.edge || d.shadow_throwing.unwrap_or(false),
                    frame: rest.frame,
                    seen_by: rest.seen_by,
                },
            )?);
        }
        self.repeat(source, placed, offsets, &name)
    }

    /// The entry's own map (its transform, then `parent`) and its array's offsets in world
    /// coordinates, if it has an array.
    fn placement(
        &self,
        source: &Source,
        transform: Option<Spanned<TransformKeys>>,
        array: Option<Spanned<ArraySection>>,
        parent: &Transform,
        name: &str,
    ) -> Result<(Transform, Option<Copies>), SceneFileError> {
        let own = match transform {
            Some(t) => {
                let span = t.span();
                let own = t.into_inner().build().map(|t| t.then(parent));
                own.and_then(|own| own.check_product().map(|()| own))
                    .map_err(|e| source.error(Some(span), format!("'{name}': {e}")))?
            }
            None => *parent,
        };
        let offsets = match array {
            Some(a) => {
                let span = a.span();
                let local = a
                    .into_inner()
                    .offsets()
                    .map_err(|e| source.error(Some(span.clone()), format!("'{name}': {e}")))?;
                Some((span, local.into_iter().map(|o| parent.vector(o)).collect()))
            }
            None => None,
        };
        Ok((own, offsets))
    }

    fn repeat(
        &self,
        source: &Source,
        placed: Placed,
        offsets: Option<Copies>,
        name: &str,
    ) -> Result<Placed, SceneFileError> {
        match offsets {
            Some((span, offsets)) => placed.repeat(&offsets).map_err(|e| {
                let message = if name.is_empty() {
                    e
                } else {
                    format!("'{name}': {e}")
                };
                source.error(Some(span), message)
            }),
            None => Ok(placed),
        }
    }
}

/// Where in the file a part's transform, shape and surface are given, for errors.
struct PartSpans {
    transform: Option<Range<usize>>,
    shape: Range<usize>,
    surface: Range<usize>,
}

/// `object`, whose shape and surface are in its entry's coordinates, placed by `own`: the
/// shape moved and the surface's positions moved with it (`Surface::transformed`).
fn place(
    source: &Source,
    own: &Transform,
    at: PartSpans,
    object: SceneObject,
) -> Result<SceneObject, SceneFileError> {
    let label = super::object_label(&object.name);
    let shape: Shape = own.shape(&object.shape).map_err(|e| {
        source.error(
            at.transform.clone().or(Some(at.shape)),
            format!("{label}: {e}"),
        )
    })?;
    let surface: Surface = object
        .surface
        .transformed(own)
        .map_err(|e| source.error(at.transform.or(Some(at.surface)), format!("{label}: {e}")))?;
    Ok(SceneObject {
        shape,
        surface,
        ..object
    })
}

fn join(prefix: &str, name: Option<&str>) -> String {
    match (prefix.is_empty(), name) {
        (_, None) => prefix.to_string(),
        (true, Some(n)) => n.to_string(),
        (false, Some(n)) => format!("{prefix}/{n}"),
    }
}

impl ArraySection {
    /// The offsets of all copies: i·a + j·b + k·c for i < n_a, j < n_b, k < n_c (first vector
    /// fastest), shifted by half the extent when centred.
    fn offsets(self) -> Result<Vec<DVec3>, String> {
        let n = self.vectors.len();
        if !(1..=3).contains(&n) {
            return Err(format!("an array needs 1, 2 or 3 vectors, got {n}"));
        }
        if self.counts.len() != n {
            return Err(format!(
                "an array needs one count per vector: {n} vectors, {} counts",
                self.counts.len()
            ));
        }
        if let Some(i) = self.vectors.iter().position(|v| v.0 == DVec3::ZERO) {
            return Err(format!("array vector {} is zero", i + 1));
        }
        // At most three counts of at most 10^7 each: the product fits in a u128.
        let total: u128 = self.counts.iter().map(|c| c.0 as u128).product();
        if total > MAX_ARRAY_ELEMENTS as u128 {
            return Err(format!(
                "the array has {total} copies; at most {MAX_ARRAY_ELEMENTS} are supported"
            ));
        }
        let start = if self.centred {
            self.vectors
                .iter()
                .zip(&self.counts)
                .map(|(v, c)| -0.5 * (c.0 - 1) as f64 * v.0)
                .sum()
        } else {
            DVec3::ZERO
        };
        let mut offsets = vec![start];
        for (v, c) in self.vectors.iter().zip(&self.counts) {
            offsets = (0..c.0)
                .flat_map(|i| offsets.iter().map(move |o| *o + i as f64 * v.0))
                .collect();
        }
        Ok(offsets)
    }
}
