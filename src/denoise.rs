//! Denoising with Intel Open Image Denoise (OIDN), the optional `denoise` feature: OIDN's `RT`
//! filter for high-dynamic-range linear renders, guided by the albedo and normal AOVs
//! (`timbre render --denoise`).

/// The denoised colours of a `width` × `height` picture: `colour`, `albedo` and `normal` are
/// its RGB, albedo and normal, three floats a pixel, row by row from the top left.
pub fn denoise(
    width: usize,
    height: usize,
    colour: &[f32],
    albedo: &[f32],
    normal: &[f32],
) -> Result<Vec<f32>, String> {
    let failed = |e: oidn::Error| format!("Open Image Denoise failed: {e}");
    let device = oidn::Device::cpu().map_err(failed)?;
    let mut denoised = vec![0.0; colour.len()];
    oidn::RayTracing::try_new(&device)
        .map_err(failed)?
        .hdr(true)
        .srgb(false)
        .image_dimensions(width, height)
        .albedo_normal(albedo, normal)
        .filter(colour, &mut denoised)
        .map_err(failed)?;
    device.get_error().map_err(failed)?;
    Ok(denoised)
}
