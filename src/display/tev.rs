//! The two packets of tev's IPC protocol that timbre sends. A packet is little-endian: a `u32`
//! length (of the whole packet, itself included), a `u8` type, then its fields; a bool is one
//! byte, a string ends with a NUL byte, `int32` and `int64` are two's complement.

/// Type of a CreateImage packet: an empty image of a size and channels (replacing one of the
/// same name).
pub const CREATE_IMAGE: u8 = 4;
/// Type of an UpdateImage packet, version 3: a rectangle's values of some channels, each read
/// from the data at its own offset and stride.
pub const UPDATE_IMAGE_V3: u8 = 6;

/// The channels timbre shows: linear R, G and B, interleaved in the data (as the EXR holds
/// them, as f32).
pub const CHANNELS: [&str; 3] = ["R", "G", "B"];

/// A packet of type `kind` whose fields `fields` appends, with its length in front; `None` if a
/// number does not fit its field.
fn packet(kind: u8, fields: impl FnOnce(&mut Vec<u8>) -> Option<()>) -> Option<Vec<u8>> {
    let mut bytes = vec![0; 4];
    bytes.push(kind);
    fields(&mut bytes)?;
    let length = u32::try_from(bytes.len()).ok()?;
    bytes[..4].copy_from_slice(&length.to_le_bytes());
    Some(bytes)
}

/// Appends `text` and its terminating NUL (`text` has none: it is a file name).
fn string(bytes: &mut Vec<u8>, text: &str) {
    bytes.extend_from_slice(text.as_bytes());
    bytes.push(0);
}

/// Appends `value` as an `int32`; `None` if it is larger.
fn int32(bytes: &mut Vec<u8>, value: u32) -> Option<()> {
    bytes.extend_from_slice(&i32::try_from(value).ok()?.to_le_bytes());
    Some(())
}

/// Appends the channel count and names.
fn channels(bytes: &mut Vec<u8>) {
    bytes.extend_from_slice(&(CHANNELS.len() as i32).to_le_bytes());
    CHANNELS.iter().for_each(|c| string(bytes, c));
}

/// CreateImage: grab focus (here: yes), the name, width, height, the channel count and the
/// channel names; `None` if a side is larger than an `int32`.
pub fn create_image(name: &str, width: u32, height: u32) -> Option<Vec<u8>> {
    packet(CREATE_IMAGE, |b| {
        b.push(1);
        string(b, name);
        int32(b, width)?;
        int32(b, height)?;
        channels(b);
        Some(())
    })
}

/// UpdateImage V3 of the `width` × `height` pixels at (`x`, `y`) of the image `name`: grab
/// focus (here: no), the name, the channel count, the channel names, x, y, width, height,
/// each channel's offset (`int64`) and stride (`int64`) into the data, then the data, f32;
/// `rgb` holds R, G, B of each pixel, row by row. `None` if a number is larger than its field.
pub fn update_image(
    name: &str,
    x: u32,
    y: u32,
    width: u32,
    height: u32,
    rgb: &[f32],
) -> Option<Vec<u8>> {
    debug_assert_eq!(rgb.len(), 3 * width as usize * height as usize);
    packet(UPDATE_IMAGE_V3, |b| {
        b.push(0);
        string(b, name);
        channels(b);
        for v in [x, y, width, height] {
            int32(b, v)?;
        }
        let n = CHANNELS.len() as i64;
        (0..n).for_each(|c| b.extend_from_slice(&c.to_le_bytes()));
        (0..n).for_each(|_| b.extend_from_slice(&n.to_le_bytes()));
        b.reserve(4 * rgb.len());
        rgb.iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
        Some(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn create_image_is_laid_out_as_tev_reads_it() {
        #[rustfmt::skip]
        let expected: Vec<u8> = vec![
            30, 0, 0, 0,                    // length: 4 + 1 + 1 + 6 + 3 × 4 + 3 × 2
            4,                              // CreateImage
            1,                              // grab focus
            b'a', b'.', b'e', b'x', b'r', 0,
            2, 0, 0, 0,                     // width
            1, 0, 0, 0,                     // height
            3, 0, 0, 0,                     // channels
            b'R', 0, b'G', 0, b'B', 0,
        ];
        assert_eq!(create_image("a.exr", 2, 1), Some(expected));
        // Sizes go out as they are, low byte first; those beyond an int32 are refused.
        let big = create_image("", 70_000, 0x0102_0304).unwrap();
        assert_eq!(&big[7..15], &[0x70, 0x11, 0x01, 0, 4, 3, 2, 1]);
        assert_eq!(create_image("", 1 << 31, 1), None);
        assert_eq!(create_image("", 1, u32::MAX), None);
    }

    #[test]
    fn update_image_v3_is_laid_out_as_tev_reads_it() {
        // Two pixels, one row: (1, 0.5, -2) and (0, 3, 0.25), at x = 3, y = 258.
        let rgb = [1.0, 0.5, -2.0, 0.0, 3.0, 0.25];
        #[rustfmt::skip]
        let expected: Vec<u8> = vec![
            106, 0, 0, 0,      // length: 4 + 1 + 1 + 2 + 4 + 6 + 16 + 24 + 24 + 24
            6,                 // UpdateImage V3
            0,                 // grab focus
            b'a', 0,
            3, 0, 0, 0,        // channels
            b'R', 0, b'G', 0, b'B', 0,
            3, 0, 0, 0,        // x
            2, 1, 0, 0,        // y = 258
            2, 0, 0, 0,        // width
            1, 0, 0, 0,        // height
            0, 0, 0, 0, 0, 0, 0, 0,  // offset of R
            1, 0, 0, 0, 0, 0, 0, 0,  // offset of G
            2, 0, 0, 0, 0, 0, 0, 0,  // offset of B
            3, 0, 0, 0, 0, 0, 0, 0,  // stride of R
            3, 0, 0, 0, 0, 0, 0, 0,  // stride of G
            3, 0, 0, 0, 0, 0, 0, 0,  // stride of B
            0, 0, 0x80, 0x3f,  // 1.0
            0, 0, 0, 0x3f,     // 0.5
            0, 0, 0, 0xc0,     // -2.0
            0, 0, 0, 0,        // 0.0
            0, 0, 0x40, 0x40,  // 3.0
            0, 0, 0x80, 0x3e,  // 0.25
        ];
        assert_eq!(update_image("a", 3, 258, 2, 1, &rgb), Some(expected));
        assert_eq!(update_image("a", 1 << 31, 0, 2, 1, &rgb), None);
    }
}
