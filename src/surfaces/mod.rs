//! Surface properties: what happens to light where a ray meets a surface. One law per file;
//! each is a pure function from the incoming ray and the surface at the hit to where the ray
//! goes on ([`Redirection`]), which the renderer traces further and ray trajectories record.
//! Nothing here traces rays or shades: that is `render`'s.

pub mod appearance;
mod chequerboard;
mod coloured;
mod constant_colour;
mod gradient_index_volume;
pub mod ideal_lenses;
pub mod lenses;
mod light_ray_field;
pub mod mesh_materials;
pub mod metatoys;
mod mirror;
mod picture;
mod refractive;
mod sky;
mod text;
mod to_shifter;
mod transparent;

pub use appearance::{
    AverageKeys, ColourFilter, ColourFilterKeys, EitherOr, EitherOrKeys, GlowingCloud,
    GlowingCloudKeys, HoleyKeys, HueBrightnessGradient, HueBrightnessGradientKeys, LayerStack,
    LayerStackKeys, Mix, PositionDependentColour, PositionDependentColourKeys, Rainbow,
    RainbowKeys, SemiTransparentKeys, SnellenChart, SnellenChartKeys, Striped, StripedKeys,
    SurfaceTiling, SurfaceTilingKeys, TimeDependentColour, TimeDependentColourKeys, TintedSolid,
    TintedSolidKeys, TwoSided, TwoSidedKeys, UsafChart, UsafChartKeys,
};
pub use chequerboard::{Chequerboard, ChequerboardKeys};
pub use coloured::{Coloured, ColouredKeys, MattKeys, ShinyKeys};
pub use constant_colour::ConstantColourKeys;
pub use gradient_index_volume::{
    GradientIndexVolume, GradientIndexVolumeKeys, IndexDistribution, Profiled, Symmetry,
};
pub use ideal_lenses::{
    Focus, Glens, GlensKeys, IdealThinCylindricalLensKeys, IdealThinCylindricalMirrorKeys,
    IdealThinLensKeys, IdealThinLensletArrayKeys, IdealThinMirrorKeys, LensletArray, ThinLens,
    ThinMirror,
};
pub use lenses::{
    EatonLensKeys, GgrinLensKeys, GradientIndexLensKeys, Lens, LuneburgLensKeys,
    MaxwellFisheyeLensKeys,
};
pub use light_ray_field::{Field, LightRayField, LightRayFieldKeys};
pub use metatoys::{
    CentralDirections, CollineationSurface, CollineationSurfaceKeys, ComplexMetarefraction,
    ComplexMetarefractionKeys, ConfocalLensletArrays, ConfocalLensletArraysKeys, DerivativeControl,
    DerivativeControlKeys, GalileoWindow, GalileoWindowKeys, IdealThinSpacePlate,
    IdealThinSpacePlateKeys, IdealisedDovePrismArray, IdealisedDovePrismArrayKeys,
    LensHologramKeys, LorentzWindow, LorentzWindowKeys, MetricInterface, MetricInterfaceKeys,
    PhaseConjugating, PhaseConjugatingKeys, PhaseHologram, PhaseHologramKeys, Pixellation,
    PixellationKeys, PointToPointImagingHologram, PointToPointImagingHologramKeys, RayFlipping,
    RayFlippingKeys, RayRotating, RayRotatingInPlaneOfIncidence, RayRotatingInPlaneOfIncidenceKeys,
    RayRotatingKeys, RefractiveComplexKeys, SpaceShifting, SpaceShiftingKeys, Teleporting,
    TeleportingKeys, VariableEtaConfocalLensletArrays, VariableEtaConfocalLensletArraysKeys,
};
pub use mirror::{Mirror, MirrorKeys, reflect};
pub use picture::{Lighting, PictureKeys, PictureSurface};
pub use refractive::{Refractive, RefractiveKeys, refract};
pub use sky::{ImageSky, SkyKeys};
pub use text::{Text, TextKeys};
pub use to_shifter::{ShiftFunction, ToShifter};
pub use transparent::{Transparent, TransparentKeys};

use glam::DVec3;

use crate::geometry::{Exit, Interaction, Shape, Transform};
use crate::keys::kinds;
use crate::math::Colour;
use crate::picture::{Picture, PictureFile};

kinds! {
    /// A `surface` table: its `type` names the law, its other keys are the law's own (read by
    /// the law's `...Keys`, in the law's file).
    pub enum SurfaceKeys -> Result<Surface, String> {
        Coloured(ColouredKeys),
        Shiny(ShinyKeys),
        Matt(MattKeys),
        #[serde(alias = "constant_colour")]
        ConstantColour(ConstantColourKeys),
        Chequerboard(ChequerboardKeys),
        Mirror(MirrorKeys),
        Refractive(RefractiveKeys),
        Transparent(TransparentKeys),
        #[serde(alias = "luneburg_lens")]
        LuneburgLens(LuneburgLensKeys),
        #[serde(alias = "eaton_lens")]
        EatonLens(EatonLensKeys),
        #[serde(alias = "maxwell_fisheye_lens")]
        MaxwellFisheyeLens(MaxwellFisheyeLensKeys),
        #[serde(alias = "ggrin_lens")]
        GgrinLens(GgrinLensKeys),
        #[serde(alias = "gradient_index_lens")]
        GradientIndexLens(GradientIndexLensKeys),
        GradientIndexVolume(GradientIndexVolumeKeys),
        #[serde(alias = "metric_interface")]
        MetricInterface(MetricInterfaceKeys),
        #[serde(alias = "confocal_lenslet_arrays", alias = "gcla")]
        ConfocalLensletArrays(ConfocalLensletArraysKeys),
        #[serde(alias = "ray_rotating")]
        RayRotating(RayRotatingKeys),
        #[serde(alias = "ray_rotating_in_plane_of_incidence")]
        RayRotatingInPlaneOfIncidence(RayRotatingInPlaneOfIncidenceKeys),
        #[serde(alias = "ray_flipping")]
        RayFlipping(RayFlippingKeys),
        IdealisedDovePrismArray(IdealisedDovePrismArrayKeys),
        IdealThinSpacePlate(IdealThinSpacePlateKeys),
        SpaceShifting(SpaceShiftingKeys),
        CollineationSurface(CollineationSurfaceKeys),
        DerivativeControl(DerivativeControlKeys),
        VariableEtaConfocalLensletArrays(VariableEtaConfocalLensletArraysKeys),
        ComplexMetarefraction(ComplexMetarefractionKeys),
        RefractiveComplex(RefractiveComplexKeys),
        #[serde(alias = "phase_hologram")]
        PhaseHologram(PhaseHologramKeys),
        PointToPointImagingHologram(PointToPointImagingHologramKeys),
        LensHologram(LensHologramKeys),
        #[serde(alias = "phase_conjugating")]
        PhaseConjugating(PhaseConjugatingKeys),
        Pixellation(PixellationKeys),
        #[serde(alias = "lorentz_window")]
        LorentzWindow(LorentzWindowKeys),
        #[serde(alias = "galileo_window")]
        GalileoWindow(GalileoWindowKeys),
        IdealThinLens(IdealThinLensKeys),
        IdealThinCylindricalLens(IdealThinCylindricalLensKeys),
        IdealThinMirror(IdealThinMirrorKeys),
        IdealThinCylindricalMirror(IdealThinCylindricalMirrorKeys),
        IdealThinLensletArray(IdealThinLensletArrayKeys),
        Glens(GlensKeys),
        Teleporting(TeleportingKeys),
        ColourFilter(ColourFilterKeys),
        TintedSolid(TintedSolidKeys),
        SemiTransparent(SemiTransparentKeys),
        Average(AverageKeys),
        TwoSided(TwoSidedKeys),
        LayerStack(LayerStackKeys),
        GlowingCloud(GlowingCloudKeys),
        LightRayField(LightRayFieldKeys),
        // Patterns and colour fields (appearance).
        Striped(StripedKeys),
        SurfaceTiling(SurfaceTilingKeys),
        TimeDependentColour(TimeDependentColourKeys),
        PositionDependentColour(PositionDependentColourKeys),
        HueBrightnessGradient(HueBrightnessGradientKeys),
        Rainbow(RainbowKeys),
        EitherOr(EitherOrKeys),
        Holey(HoleyKeys),
        UsafChart(UsafChartKeys),
        SnellenChart(SnellenChartKeys),
        Picture(PictureKeys),
        Text(TextKeys),
    }
}

impl SurfaceKeys {
    /// The picture files the surface names, its parts' too, for the scene-file reader to open
    /// before the surface is built. A kind with a picture file, or with surfaces of its own,
    /// says so here.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        match self {
            SurfaceKeys::Chequerboard(keys) => keys.pictures(),
            SurfaceKeys::SemiTransparent(keys) => keys.pictures(),
            SurfaceKeys::Average(keys) => keys.pictures(),
            SurfaceKeys::TwoSided(keys) => keys.pictures(),
            SurfaceKeys::LayerStack(keys) => keys.pictures(),
            SurfaceKeys::Striped(keys) => keys.pictures(),
            SurfaceKeys::SurfaceTiling(keys) => keys.pictures(),
            SurfaceKeys::Picture(keys) => keys.pictures(),
            SurfaceKeys::Text(keys) => keys.pictures(),
            SurfaceKeys::EitherOr(keys) => keys.pictures(),
            SurfaceKeys::Holey(keys) => keys.pictures(),
            SurfaceKeys::UsafChart(keys) => keys.pictures(),
            SurfaceKeys::SnellenChart(keys) => keys.pictures(),
            _ => Vec::new(),
        }
    }

    /// The name of the object a teleporting surface leads to.
    pub fn destination(&self) -> Option<&str> {
        if let SurfaceKeys::Teleporting(keys) = self {
            Some(&keys.destination)
        } else {
            None
        }
    }
}

/// What a surface's law does with a ray that meets it: the one place each law is applied, both
/// by the renderer and by ray trajectories. A `factor` is the fraction of each colour channel
/// (red, green, blue) passed on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Redirection<'a> {
    /// The ray ends on a surface of these colours lit by the scene's lights, which the
    /// renderer shades.
    Lit(Coloured),
    /// The ray ends on a surface that emits this colour whatever the lighting (TIM's sky).
    Emits(Colour),
    /// No light comes back along the ray: a ray trapped in a lens, teleported beyond the
    /// destination's edge, or meeting a law on a shape it does not work on (a lens that is not
    /// a sphere, a hologram on a part without surface coordinates; `timbre check` warns of
    /// these).
    Lost,
    /// The ray leaves the hit point in unit `direction`, carrying `factor` of the light.
    Leaves { direction: DVec3, factor: Colour },
    /// The ray crosses the object and leaves where `exit` says (§3's lenses).
    Crosses { exit: Exit, factor: Colour },
    /// The ray leaves from another surface, without travelling between (teleporting).
    Jumps { exit: Exit, factor: Colour },
    /// The ray enters an absorbing solid (Dr TIM's `SurfaceOfTintedSolid`) in unit
    /// `direction` (its own, or refracted by a layer in front), carrying `factor` of the
    /// light: along the distance t to its next hit each channel keeps exp(−absorption·t) of
    /// the light, unless that hit is on the same object, whose exit then accounts for the
    /// whole path.
    Absorbs {
        absorption: Colour,
        direction: DVec3,
        factor: Colour,
    },
    /// The ray goes on undeviated, carrying `factor` of the light it brings, and `glow` is
    /// added (Dr TIM's `SurfaceOfGlowingCloud`, factor 1, and `Rainbow`).
    Glows { glow: Colour, factor: Colour },
    /// The light is the sum of what several surfaces at the same point pass on, each part
    /// weighted per channel (semi-transparent surfaces, averages).
    Mixes(&'a [Weighted]),
}

/// One part of a mixed surface: a surface and the fraction of each colour channel it adds.
#[derive(Debug, Clone, PartialEq)]
pub struct Weighted {
    pub weight: Colour,
    pub surface: Surface,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Surface {
    /// Diffuse and specular colours lit by the scene's lights.
    Coloured(Coloured),
    /// Emits its colour whatever the lighting (TIM's sky).
    ConstantColour(Colour),
    Chequerboard(Chequerboard),
    Mirror(Mirror),
    Refractive(Refractive),
    Transparent(Transparent),
    /// §3's lenses; the surface of a sphere.
    Lens(Lens),
    /// A convex solid filled with a gradient-index medium.
    GradientIndexVolume(GradientIndexVolume),
    /// A transformation-optics shifter's shell; the surface of its two spheres (a device's).
    ToShifter(ToShifter),
    /// §4: refraction between spaces with different optical metrics.
    MetricInterface(MetricInterface),
    /// §5: generalised confocal lenslet arrays.
    ConfocalLensletArrays(ConfocalLensletArrays),
    RayRotating(RayRotating),
    RayRotatingInPlaneOfIncidence(RayRotatingInPlaneOfIncidence),
    Pixellation(Pixellation),
    IdealisedDovePrismArray(IdealisedDovePrismArray),
    IdealThinSpacePlate(IdealThinSpacePlate),
    /// Dr TIM's space-shifting plane.
    SpaceShifting(SpaceShifting),
    CollineationSurface(CollineationSurface),
    DerivativeControl(DerivativeControl),
    VariableEtaConfocalLensletArrays(VariableEtaConfocalLensletArrays),
    ComplexMetarefraction(ComplexMetarefraction),
    RayFlipping(RayFlipping),
    /// Charted shapes only (plane coordinates or coordinate axes on every part).
    PhaseHologram(PhaseHologram),
    /// Any shape: the law needs positions, not surface coordinates.
    PointToPointImagingHologram(PointToPointImagingHologram),
    PhaseConjugating(PhaseConjugating),
    LorentzWindow(LorentzWindow),
    GalileoWindow(GalileoWindow),
    Teleporting(Teleporting),
    /// Ideal thin lenses, spherical and cylindrical, on any shape.
    IdealThinLens(ThinLens),
    IdealThinMirror(ThinMirror),
    IdealThinLensletArray(LensletArray),
    Glens(Glens),
    ColourFilter(ColourFilter),
    TintedSolid(TintedSolid),
    /// A surface and a transparent part, mixed.
    SemiTransparent(Mix),
    Average(Mix),
    TwoSided(TwoSided),
    LayerStack(LayerStack),
    GlowingCloud(GlowingCloud),
    LightRayField(LightRayField),
    /// Patterns and colour fields (appearance); the patterns need surface coordinates.
    Striped(Striped),
    SurfaceTiling(SurfaceTiling),
    TimeDependentColour(TimeDependentColour),
    PositionDependentColour(PositionDependentColour),
    /// Charted shapes only.
    HueBrightnessGradient(HueBrightnessGradient),
    Rainbow(Rainbow),
    /// A mask choosing between two surfaces (also a holey surface); charted shapes only.
    EitherOr(EitherOr),
    /// Test charts; charted shapes only.
    UsafChart(UsafChart),
    SnellenChart(SnellenChart),
    /// A picture on the shape's surface coordinates (charted shapes only).
    Picture(PictureSurface),
    /// An equirectangular picture of the sky at infinity, picked by the ray's direction.
    ImageSky(ImageSky),
    /// A mesh material with MTL `d` < 1 ([`mesh_materials`]).
    Dissolved(mesh_materials::Dissolved),
    /// A mesh material with a texture (MTL `map_Kd`).
    Textured(mesh_materials::Textured),
    /// A mesh's vertex colours.
    VertexColours(mesh_materials::VertexColours),
    /// Letters of the shipped font on a background.
    Text(Text),
}

impl Surface {
    /// The kind of surface, in the scene file's words (the §3 lenses are all `lens`).
    pub fn kind(&self) -> &'static str {
        match self {
            Surface::Coloured(_) => "coloured",
            Surface::ConstantColour(_) => "constant-colour",
            Surface::Chequerboard(_) => "chequerboard",
            Surface::Mirror(_) => "mirror",
            Surface::Refractive(_) => "refractive",
            Surface::Transparent(_) => "transparent",
            Surface::Lens(_) => "lens",
            Surface::ToShifter(_) => "to-shifter",
            Surface::GradientIndexVolume(_) => "gradient-index-volume",
            Surface::MetricInterface(_) => "metric-interface",
            Surface::ConfocalLensletArrays(_) => "confocal-lenslet-arrays",
            Surface::RayRotating(_) => "ray-rotating",
            Surface::RayRotatingInPlaneOfIncidence(_) => "ray-rotating-in-plane-of-incidence",
            Surface::Pixellation(_) => "pixellation",
            Surface::IdealisedDovePrismArray(_) => "idealised-dove-prism-array",
            Surface::IdealThinSpacePlate(_) => "ideal-thin-space-plate",
            Surface::SpaceShifting(_) => "space-shifting",
            Surface::CollineationSurface(_) => "collineation-surface",
            Surface::DerivativeControl(_) => "derivative-control",
            Surface::VariableEtaConfocalLensletArrays(_) => "variable-eta-confocal-lenslet-arrays",
            Surface::ComplexMetarefraction(_) => "complex-metarefraction",
            Surface::RayFlipping(_) => "ray-flipping",
            Surface::PhaseHologram(_) => "phase-hologram",
            Surface::PointToPointImagingHologram(_) => "point-to-point-imaging-hologram",
            Surface::PhaseConjugating(_) => "phase-conjugating",
            Surface::LorentzWindow(_) => "lorentz-window",
            Surface::GalileoWindow(_) => "galileo-window",
            Surface::Teleporting(_) => "teleporting",
            Surface::IdealThinLens(_) => "ideal-thin-lens",
            Surface::IdealThinMirror(_) => "ideal-thin-mirror",
            Surface::IdealThinLensletArray(_) => "ideal-thin-lenslet-array",
            Surface::Glens(_) => "glens",
            Surface::ColourFilter(_) => "colour-filter",
            Surface::TintedSolid(_) => "tinted-solid",
            Surface::SemiTransparent(_) => "semi-transparent",
            Surface::Average(_) => "average",
            Surface::TwoSided(_) => "two-sided",
            Surface::LayerStack(_) => "layer-stack",
            Surface::GlowingCloud(_) => "glowing-cloud",
            Surface::LightRayField(_) => "light-ray-field",
            Surface::Striped(_) => "striped",
            Surface::SurfaceTiling(_) => "surface-tiling",
            Surface::TimeDependentColour(_) => "time-dependent-colour",
            Surface::PositionDependentColour(_) => "position-dependent-colour",
            Surface::HueBrightnessGradient(_) => "hue-brightness-gradient",
            Surface::Rainbow(_) => "rainbow",
            Surface::EitherOr(_) => "either-or",
            Surface::UsafChart(_) => "usaf-chart",
            Surface::SnellenChart(_) => "snellen-chart",
            Surface::Picture(_) => "picture",
            Surface::ImageSky(_) => "image-sky",
            Surface::Dissolved(_) => "mesh material",
            Surface::Textured(_) => "textured mesh material",
            Surface::VertexColours(_) => "vertex colours",
            Surface::Text(_) => "text",
        }
    }

    /// Where the ray `at.ray` goes on from this surface. `inside` is shown the points of the
    /// curved path of a ray integrated through a gradient-index lens, between entry and exit.
    #[inline]
    pub fn redirect(&self, at: &Interaction, inside: &mut dyn FnMut(DVec3)) -> Redirection<'_> {
        match self {
            Surface::Coloured(s) => Redirection::Lit(*s),
            Surface::ConstantColour(c) => Redirection::Emits(*c),
            Surface::Chequerboard(s) => s.tile_at(at).redirect(at, inside),
            Surface::SemiTransparent(m) | Surface::Average(m) => m.redirect(),
            Surface::TwoSided(s) => s.redirect(at, inside),
            Surface::Striped(s) => s.stripe_at(at).redirect(at, inside),
            Surface::SurfaceTiling(s) => s.tile_at(at).redirect(at, inside),
            Surface::TimeDependentColour(s) => s.redirect(at),
            Surface::PositionDependentColour(s) => s.redirect(at),
            Surface::HueBrightnessGradient(s) => s.redirect(at),
            Surface::EitherOr(s) => s.surface_at(at).redirect(at, inside),
            Surface::UsafChart(s) => s.surface_at(at).redirect(at, inside),
            Surface::SnellenChart(s) => s.surface_at(at).redirect(at, inside),
            Surface::Dissolved(d) => Redirection::Mixes(&d.parts[..]),
            Surface::Text(s) => s.surface_at(at).redirect(at, inside),
            _ => self.redirect_by_law(at, inside),
        }
    }

    /// [`Self::redirect`] of the surfaces that send the ray on, out of line so that the common
    /// surfaces with a colour of their own are dispatched without its large stack frame.
    #[inline(never)]
    fn redirect_by_law(
        &self,
        at: &Interaction,
        inside: &mut dyn FnMut(DVec3),
    ) -> Redirection<'static> {
        let redirection = match self {
            Surface::Coloured(_)
            | Surface::ConstantColour(_)
            | Surface::Chequerboard(_)
            | Surface::SemiTransparent(_)
            | Surface::Average(_)
            | Surface::TwoSided(_)
            | Surface::Striped(_)
            | Surface::SurfaceTiling(_)
            | Surface::TimeDependentColour(_)
            | Surface::PositionDependentColour(_)
            | Surface::HueBrightnessGradient(_)
            | Surface::EitherOr(_)
            | Surface::UsafChart(_)
            | Surface::SnellenChart(_)
            | Surface::Dissolved(_)
            | Surface::Text(_) => {
                unreachable!("answered by Surface::redirect itself")
            }
            Surface::Mirror(s) => s.redirect(at),
            Surface::Refractive(s) => s.redirect(at),
            Surface::Transparent(s) => s.redirect(at),
            Surface::Lens(s) => s.redirect(at, inside),
            Surface::ToShifter(s) => s.redirect(at, inside),
            Surface::GradientIndexVolume(s) => s.redirect(at, inside),
            Surface::MetricInterface(s) => s.redirect(at),
            Surface::ConfocalLensletArrays(s) => s.redirect(at),
            Surface::RayRotating(s) => s.redirect(at),
            Surface::RayRotatingInPlaneOfIncidence(s) => s.redirect(at),
            Surface::Pixellation(s) => s.redirect(at),
            Surface::IdealisedDovePrismArray(s) => s.redirect(at),
            Surface::IdealThinSpacePlate(s) => s.redirect(at),
            Surface::SpaceShifting(s) => s.redirect(at),
            Surface::CollineationSurface(s) => s.redirect(at),
            Surface::DerivativeControl(s) => s.redirect(at),
            Surface::VariableEtaConfocalLensletArrays(s) => s.redirect(at),
            Surface::ComplexMetarefraction(s) => s.redirect(at),
            Surface::RayFlipping(s) => s.redirect(at),
            Surface::PhaseHologram(s) => s.redirect(at),
            Surface::PointToPointImagingHologram(s) => s.redirect(at),
            Surface::PhaseConjugating(s) => s.redirect(at),
            Surface::LorentzWindow(s) => s.redirect(at),
            Surface::GalileoWindow(s) => s.redirect(at),
            Surface::Teleporting(s) => s.redirect(at),
            Surface::IdealThinLens(s) => s.redirect(at),
            Surface::IdealThinMirror(s) => s.redirect(at),
            Surface::IdealThinLensletArray(s) => s.redirect(at),
            Surface::Glens(s) => s.redirect(at),
            Surface::Rainbow(s) => s.redirect(at),
            Surface::ColourFilter(s) => s.redirect(at),
            Surface::TintedSolid(s) => s.redirect(at),
            Surface::LayerStack(s) => s.redirect(at),
            Surface::GlowingCloud(s) => s.redirect(at),
            Surface::LightRayField(s) => s.redirect(at),
            Surface::Picture(s) => s.redirect(at),
            Surface::ImageSky(s) => s.redirect(at),
            Surface::Textured(s) => s.redirect(at),
            Surface::VertexColours(s) => s.redirect(at),
        };
        // A direction or exit that overflowed f64 (a law at an extreme of its parameters) passes
        // no light on, rather than a NaN ray.
        let finite = |exit: &Exit| exit.point.is_finite() && exit.direction.is_finite();
        match redirection {
            Redirection::Leaves { direction, .. } if !direction.is_finite() => Redirection::Lost,
            Redirection::Crosses { exit, .. } | Redirection::Jumps { exit, .. }
                if !finite(&exit) =>
            {
                Redirection::Lost
            }
            r => r,
        }
    }

    /// The surface of an object placed by `t`: the positions and directions of the laws that
    /// have them move with the shape (ideal lenses, point-to-point holograms, light-ray fields,
    /// Dove-prism arrays, space plates, space-shifting planes' offsets, gradient-index volumes'
    /// centres, axes and normals, variable-η CLAs, collineations, gCLAs made as a device's
    /// imaging surfaces, and a pixellation's sides where they are given in the scene), and
    /// their lengths scale with it where that needs a
    /// similarity map. The other laws have no positions; the vectors and tensors of a law in
    /// the global basis are read in x, y and z, and pixel sizes and
    /// wavelengths stay as given, wherever the object is.
    pub fn transformed(&self, t: &Transform) -> Result<Surface, String> {
        if t.is_identity() {
            return Ok(self.clone());
        }
        Ok(match self {
            Surface::IdealThinLens(l) => Surface::IdealThinLens(l.transformed(t)?),
            Surface::IdealThinMirror(m) => Surface::IdealThinMirror(ThinMirror {
                lens: m.lens.transformed(t)?,
            }),
            Surface::IdealThinLensletArray(a) => Surface::IdealThinLensletArray(a.transformed(t)?),
            Surface::Glens(g) => Surface::Glens(g.transformed(t)?),
            Surface::PointToPointImagingHologram(h) => {
                Surface::PointToPointImagingHologram(h.transformed(t))
            }
            Surface::LightRayField(f) => Surface::LightRayField(f.transformed(t)?),
            Surface::Pixellation(p) => Surface::Pixellation(p.transformed(t)?),
            Surface::IdealThinSpacePlate(p) => Surface::IdealThinSpacePlate(p.transformed(t)?),
            Surface::SpaceShifting(s) => Surface::SpaceShifting(s.transformed(t)),
            Surface::GradientIndexVolume(v) => Surface::GradientIndexVolume(v.transformed(t)?),
            Surface::CollineationSurface(c) => Surface::CollineationSurface(c.transformed(t)),
            Surface::DerivativeControl(d) => Surface::DerivativeControl(d.transformed(t)?),
            Surface::VariableEtaConfocalLensletArrays(a) => {
                Surface::VariableEtaConfocalLensletArrays(a.transformed(t)?)
            }
            Surface::ConfocalLensletArrays(a) => Surface::ConfocalLensletArrays(a.transformed(t)?),
            Surface::IdealisedDovePrismArray(a) => {
                Surface::IdealisedDovePrismArray(a.transformed(t)?)
            }
            Surface::Chequerboard(c) => Surface::Chequerboard(Chequerboard {
                tile_width: c.tile_width,
                surfaces: transformed_pair(&c.surfaces, t)?,
            }),
            Surface::SemiTransparent(m) => Surface::SemiTransparent(m.transformed(t)?),
            Surface::Average(m) => Surface::Average(m.transformed(t)?),
            Surface::TwoSided(s) => Surface::TwoSided(TwoSided {
                sides: transformed_pair(&s.sides, t)?,
            }),
            Surface::LayerStack(s) => Surface::LayerStack(LayerStack {
                layers: s
                    .layers
                    .iter()
                    .map(|l| l.transformed(t))
                    .collect::<Result<_, String>>()?,
            }),
            Surface::Striped(s) => Surface::Striped(Striped {
                width: s.width,
                surfaces: transformed_pair(&s.surfaces, t)?,
            }),
            Surface::SurfaceTiling(s) => Surface::SurfaceTiling(SurfaceTiling {
                widths: s.widths,
                surfaces: transformed_pair(&s.surfaces, t)?,
            }),
            Surface::Text(c) => Surface::Text(Text {
                lines: c.lines.clone(),
                surfaces: transformed_pair(&c.surfaces, t)?,
            }),
            Surface::EitherOr(e) => Surface::EitherOr(EitherOr {
                surfaces: transformed_pair(&e.surfaces, t)?,
                ..e.clone()
            }),
            Surface::UsafChart(c) => Surface::UsafChart(UsafChart {
                bars: c.bars.clone(),
                surfaces: transformed_pair(&c.surfaces, t)?,
            }),
            Surface::SnellenChart(c) => Surface::SnellenChart(SnellenChart {
                lines: c.lines.clone(),
                surfaces: transformed_pair(&c.surfaces, t)?,
            }),
            Surface::Rainbow(r) => Surface::Rainbow(r.transformed(t)),
            Surface::Teleporting(s) => Surface::Teleporting(s.transformed(t)?),
            Surface::ToShifter(s) => Surface::ToShifter(s.transformed(t)?),
            Surface::PositionDependentColour(c) => {
                Surface::PositionDependentColour(c.transformed(t))
            }
            Surface::TimeDependentColour(_)
            | Surface::HueBrightnessGradient(_)
            | Surface::Coloured(_)
            | Surface::ConstantColour(_)
            | Surface::ColourFilter(_)
            | Surface::TintedSolid(_)
            | Surface::GlowingCloud(_)
            | Surface::Mirror(_)
            | Surface::Refractive(_)
            | Surface::Transparent(_)
            | Surface::Lens(_)
            | Surface::MetricInterface(_)
            | Surface::RayRotating(_)
            | Surface::RayRotatingInPlaneOfIncidence(_)
            | Surface::ComplexMetarefraction(_)
            | Surface::RayFlipping(_)
            | Surface::PhaseHologram(_)
            | Surface::PhaseConjugating(_)
            | Surface::LorentzWindow(_)
            | Surface::GalileoWindow(_)
            | Surface::Picture(_)
            | Surface::ImageSky(_)
            | Surface::Dissolved(_)
            | Surface::Textured(_)
            | Surface::VertexColours(_) => self.clone(),
        })
    }

    /// The pictures the surface shows, its parts' too (shared pictures as often as they
    /// appear).
    pub fn pictures(&self) -> Vec<&Picture> {
        let own = match self {
            Surface::Picture(s) => Some(&s.picture),
            Surface::ImageSky(s) => Some(&s.picture),
            Surface::Textured(s) => Some(&s.picture),
            Surface::EitherOr(s) => Some(&s.mask),
            _ => None,
        };
        own.into_iter()
            .chain(self.parts().into_iter().flat_map(Surface::pictures))
            .collect()
    }

    /// The surfaces this one is made of (none for a surface of one law).
    pub fn parts(&self) -> Vec<&Surface> {
        match self {
            Surface::Chequerboard(Chequerboard { surfaces, .. })
            | Surface::Striped(Striped { surfaces, .. })
            | Surface::SurfaceTiling(SurfaceTiling { surfaces, .. })
            | Surface::Text(Text { surfaces, .. })
            | Surface::EitherOr(EitherOr { surfaces, .. })
            | Surface::UsafChart(UsafChart { surfaces, .. })
            | Surface::SnellenChart(SnellenChart { surfaces, .. })
            | Surface::TwoSided(TwoSided {
                sides: surfaces, ..
            }) => surfaces.iter().collect(),
            Surface::LayerStack(s) => s.layers.iter().collect(),
            Surface::SemiTransparent(m) | Surface::Average(m) => {
                m.parts.iter().map(|p| &p.surface).collect()
            }
            Surface::Dissolved(d) => d.parts.iter().map(|p| &p.surface).collect(),
            _ => Vec::new(),
        }
    }

    /// Whether the law works on `shape`: §3's lenses, also as parts of other surfaces, need a
    /// sphere's centre and radius; phase holograms, pictures, patterns, masks, text and charts
    /// need surface coordinates on every part (plane coordinates or coordinate axes); a mesh's
    /// texture needs its texture coordinates. The other laws work on any shape.
    pub fn check_shape(&self, shape: &Shape) -> Result<(), String> {
        match self {
            Surface::Lens(l) if !matches!(shape, Shape::Sphere(_)) => Err(format!(
                "a {} surface needs a sphere shape (its centre and radius)",
                l.law.name()
            )),
            Surface::ToShifter(_) if !matches!(shape, Shape::Sphere(_)) => {
                Err("a to-shifter surface needs a sphere shape".to_string())
            }
            Surface::GradientIndexVolume(_) if shape.analytic_solid().is_none() => Err(
                "a gradient-index-volume surface needs a convex solid shape (a sphere, cuboid, \
                 parallelepiped, prism, Platonic solid, ellipsoid, closed cylinder, elliptic \
                 cylinder or cone, closed paraboloid, convex lens surface or half-space plane, \
                 or one of them transformed)"
                    .to_string(),
            ),
            Surface::Textured(_) if !matches!(shape, Shape::TriangleMesh(m) if m.uvs().is_some()) => {
                Err(
                    "a textured material (MTL map_Kd) needs texture coordinates (OBJ vt) on \
                     every face of its part"
                        .to_string(),
                )
            }
            Surface::DerivativeControl(d) if d.pixels.is_some() && !shape.is_flat() => Err(
                "a pixellated derivative-control surface needs a flat shape (its pixels are \
                 cells of the plane coordinates)"
                    .to_string(),
            ),
            _ if self.needs_coordinates() && !shape.is_charted() => Err(format!(
                "a {} surface needs surface coordinates on every part of its shape (a flat \
                 shape, a polyhedron, a sphere, ellipsoid, paraboloid, spherical cap, bilinear \
                 surface, cylinder or cone with open = true, or one of them transformed); a \
                 closed cylinder's or cone's caps and meshes have none",
                self.kind()
            )),
            _ => self
                .parts()
                .into_iter()
                .try_for_each(|s| s.check_shape(shape)),
        }
    }

    /// Whether the law reads the shape's surface coordinates.
    fn needs_coordinates(&self) -> bool {
        matches!(
            self,
            Surface::PhaseHologram(_)
                | Surface::Picture(_)
                | Surface::Striped(_)
                | Surface::SurfaceTiling(_)
                | Surface::Text(_)
                | Surface::EitherOr(_)
                | Surface::UsafChart(_)
                | Surface::SnellenChart(_)
                | Surface::HueBrightnessGradient(_)
        )
    }
}

/// Both surfaces of a two-part surface, for an object placed by `t`.
fn transformed_pair(pair: &[Surface; 2], t: &Transform) -> Result<Box<[Surface; 2]>, String> {
    Ok(Box::new([pair[0].transformed(t)?, pair[1].transformed(t)?]))
}

#[cfg(test)]
pub(crate) mod tests {
    //! What the surface laws' tests share: interactions of rays with a shape alone (no scene),
    //! and the parts of a redirection they check.

    use glam::DVec3;

    use super::Redirection;
    use crate::geometry::{Exit, Interaction, Shape};
    use crate::math::Ray;

    /// The ray from `origin` along `direction` (normalised here) meeting `shape` at its
    /// nearest hit ahead; panics if it misses.
    pub(crate) fn meet(shape: &Shape, origin: DVec3, direction: DVec3) -> Interaction<'_> {
        meet_copy(shape, DVec3::ZERO, origin, direction)
    }

    /// The same on the array copy of `shape` moved by `offset` (the ray is in world
    /// coordinates; the copy is the shape translated by `offset`).
    pub(crate) fn meet_copy(
        shape: &Shape,
        offset: DVec3,
        origin: DVec3,
        direction: DVec3,
    ) -> Interaction<'_> {
        let ray = Ray::new(origin, direction, 0.0);
        let (t, prim) = shape
            .intersect(origin - offset, ray.direction, 0.0, f64::INFINITY)
            .expect("the test ray meets the shape");
        Interaction {
            offset,
            ..Interaction::on(shape, ray, t, prim)
        }
    }

    /// The direction and factor of a ray that leaves the hit point; panics on any other
    /// redirection.
    pub(crate) fn leaves(r: Redirection) -> (DVec3, f64) {
        match r {
            Redirection::Leaves { direction, factor } => (direction, grey(factor)),
            other => panic!("expected the ray to leave the hit point, got {other:?}"),
        }
    }

    /// The exit and factor of a ray that crosses the object; panics on any other redirection.
    pub(crate) fn crosses(r: Redirection) -> (Exit, f64) {
        match r {
            Redirection::Crosses { exit, factor } => (exit, grey(factor)),
            other => panic!("expected the ray to cross the object, got {other:?}"),
        }
    }

    /// The one value of a factor that is the same in every channel; panics otherwise.
    pub(crate) fn grey(factor: crate::math::Colour) -> f64 {
        assert!(
            factor.x == factor.y && factor.y == factor.z,
            "a grey factor: {factor}"
        );
        factor.x
    }

    /// The distance of `target` from the line through `s` along `direction`, and how far along
    /// the line (in units of |direction|, negative behind `s`) its foot is.
    pub(crate) fn line_miss(s: DVec3, direction: DVec3, target: DVec3) -> (f64, f64) {
        let e = direction.normalize();
        let along = (target - s).dot(e);
        ((target - s - along * e).length(), along)
    }
}
