//! A scene made ready to render in one call, [`prepare`]: its render settings and stereo output
//! checked, the memory the render will need refused up front if it cannot be had (a clear
//! error, never an abort midway), the Embree device made, the ray trajectories drawn and the
//! BVH built. The CLI, `timbre serve`, Python and the fuzzers all prepare scenes through it.

use thiserror::Error;

use crate::embree::{Device, EmbreeError};
use crate::memory;
use crate::scene::{BuildError, RenderSettings, Scene, SceneDescription, Stereo};
use crate::stereo;
use crate::trajectories::{self, TrajectoryError};

/// Why a scene could not be made ready.
#[derive(Debug, Error)]
pub enum PrepareError {
    /// The render settings are out of range (the user's to fix).
    #[error("{0}")]
    Settings(String),
    /// The stereo output does not fit the image size (the user's to fix, in the scene file).
    #[error("{0}")]
    Stereo(String),
    /// More memory than can be had (the user's to fix: a smaller image or scene, or fewer
    /// triangles asked of `timbre generate-mesh`; `advice` says which).
    #[error(
        "{what} needs about {:.2} GiB of memory{}, but only {:.2} GiB can be had here (free memory, or the process's address-space limit); {advice}",
        gib(image.saturating_add(*scene)), bvh_share(*scene), gib(*available)
    )]
    Memory {
        what: String,
        image: u64,
        scene: u64,
        available: u64,
        advice: &'static str,
    },
    /// The ray trajectories could not be traced (too many points: the user's; Embree's).
    #[error(transparent)]
    Trajectories(#[from] TrajectoryError),
    #[error(transparent)]
    Embree(#[from] EmbreeError),
    #[error(transparent)]
    Build(#[from] BuildError),
}

impl PrepareError {
    /// Whether the scene file or the options asked for what cannot be done (rather than
    /// Embree failing).
    pub fn is_bad_input(&self) -> bool {
        match self {
            PrepareError::Settings(_) | PrepareError::Stereo(_) | PrepareError::Memory { .. } => {
                true
            }
            PrepareError::Trajectories(e) => !matches!(e, TrajectoryError::Embree(_)),
            PrepareError::Embree(_) | PrepareError::Build(_) => false,
        }
    }
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1 << 30)
}

/// The scene's BVH's share of the memory error, where the work has a scene to build.
fn bvh_share(scene: u64) -> String {
    match scene {
        0 => String::new(),
        _ => format!(" ({:.2} GiB for the scene's BVH)", gib(scene)),
    }
}

/// What to make smaller when `image` and `scene` bytes do not fit.
fn memory_advice(image: u64, scene: u64) -> &'static str {
    if scene > image {
        "give the scene fewer array copies, triangles or objects"
    } else {
        "render a smaller image"
    }
}

/// What a render needs besides the scene's BVH, for the memory check.
#[derive(Debug, Clone)]
pub struct Needs {
    /// What is prepared, as the memory error names it: "a 640x480 render", "checking x.toml".
    pub what: String,
    /// Bytes of the image buffers the render holds beside the scene (0 for a check).
    pub image: u64,
    /// Address space the render will map besides its buffers and has not mapped yet
    /// ([`memory::reserve`] of its threads, less what earlier renders of the process mapped).
    pub reserve: u64,
}

impl Needs {
    /// A render of `image` bytes with `threads` threads, in a process that has rendered none.
    pub fn render(what: String, image: u64, threads: usize) -> Needs {
        Needs {
            what,
            image,
            reserve: memory::reserve(threads as u64),
        }
    }

    /// Building the scene alone (with Embree's threads, one a core), for `what`.
    pub fn scene(what: String) -> Needs {
        Needs::render(what, 0, default_threads())
    }
}

/// The threads a render uses when not told: one a core.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A scene ready to render, and the Embree device it lives on (which must outlive it).
pub struct Ready {
    pub scene: Scene,
    pub device: Device,
}

/// Checks that `settings` are in range and that the scene's stereo output fits them.
pub fn check_settings(settings: &RenderSettings, stereo: &Stereo) -> Result<(), PrepareError> {
    settings.validate().map_err(PrepareError::Settings)?;
    stereo::validate(stereo, settings.width, settings.height).map_err(PrepareError::Stereo)
}

/// Refuses a render whose image buffers and `scene` bytes (the BVH's, 0 when it is built
/// already) would need more memory than can be had here.
pub fn check_memory(needs: &Needs, scene: u64) -> Result<(), PrepareError> {
    refuse_beyond(needs, scene, memory_advice(needs.image, scene))
}

/// Refuses work that builds no scene (`timbre generate-mesh`'s mesh) whose buffers,
/// `needs.image` bytes, would need more memory than can be had here, in [`check_memory`]'s
/// words; `advice` says what to ask less of.
pub fn check_work_memory(needs: &Needs, advice: &'static str) -> Result<(), PrepareError> {
    refuse_beyond(needs, 0, advice)
}

/// The memory check of [`check_memory`] and [`check_work_memory`].
fn refuse_beyond(needs: &Needs, scene: u64, advice: &'static str) -> Result<(), PrepareError> {
    match memory::available(needs.reserve) {
        Some(available) if needs.image.saturating_add(scene) > available => {
            Err(PrepareError::Memory {
                what: needs.what.clone(),
                image: needs.image,
                scene,
                available,
                advice,
            })
        }
        _ => Ok(()),
    }
}

/// An Embree device with `threads` threads (Embree's default, one a core, when not given).
pub fn device(threads: Option<usize>) -> Result<Device, PrepareError> {
    let config = threads.map_or_else(String::new, |t| format!("threads={t}"));
    Ok(Device::new(&config)?)
}

/// The scene of `description` on `device`: its ray trajectories drawn, its BVH built.
pub fn build(device: &Device, description: &SceneDescription) -> Result<Scene, PrepareError> {
    let drawn = trajectories::draw(device, description)?;
    Ok(Scene::build(device, &drawn)?)
}

/// `description` made ready to render with `settings` (the settings checked, the memory
/// `needs` checked with the scene's BVH, a device of the settings' threads, trajectories
/// drawn, the BVH built).
pub fn prepare(
    description: &SceneDescription,
    settings: &RenderSettings,
    needs: &Needs,
) -> Result<Ready, PrepareError> {
    check_settings(settings, &description.stereo)?;
    check_memory(needs, description.build_memory())?;
    let device = device(settings.threads)?;
    let scene = build(&device, description)?;
    Ok(Ready { scene, device })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Needs of `bytes` of buffers: far more than any machine has (Linux always says what it
    /// has available).
    fn huge(bytes: u64) -> Needs {
        Needs {
            what: "the work".into(),
            image: bytes,
            reserve: 0,
        }
    }

    #[test]
    fn work_without_a_scene_is_refused_in_the_same_words_with_its_own_advice() {
        let e = check_work_memory(&huge(1 << 60), "ask for less").unwrap_err();
        assert!(e.is_bad_input());
        let message = e.to_string();
        assert!(
            message.starts_with("the work needs about 1073741824.00 GiB of memory, but only ")
                && message.ends_with("can be had here (free memory, or the process's address-space limit); ask for less"),
            "{message}"
        );
        let e = check_memory(&huge(1 << 40), 1 << 60)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("GiB of memory (1073741824.00 GiB for the scene's BVH), but only")
                && e.ends_with("give the scene fewer array copies, triangles or objects"),
            "{e}"
        );
        let e = check_memory(&huge(1 << 60), 0).unwrap_err().to_string();
        assert!(
            !e.contains("BVH") && e.ends_with("render a smaller image"),
            "{e}"
        );
    }

    #[test]
    fn sums_beyond_u64_are_refused_not_wrapped() {
        let e = check_memory(&huge(u64::MAX), u64::MAX).unwrap_err();
        assert!(e.to_string().contains("needs about"), "{e}");
        assert!(check_work_memory(&huge(0), "ask for less").is_ok());
    }
}
