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

/// A packet of type `kind` whose fields `fields` appends, with its length in front.
fn packet(kind: u8, fields: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut bytes = vec![0; 4];
    bytes.push(kind);
    fields(&mut bytes);
    let length = bytes.len() as u32;
    bytes[..4].copy_from_slice(&length.to_le_bytes());
    bytes
}

/// Appends `text` and its terminating NUL (`text` has none: it is a file name).
fn string(bytes: &mut Vec<u8>, text: &str) {
    bytes.extend_from_slice(text.as_bytes());
    bytes.push(0);
}

fn int32(bytes: &mut Vec<u8>, value: u32) {
    bytes.extend_from_slice(&(value as i32).to_le_bytes());
}

/// CreateImage: grab focus (here: yes), the name, width, height, the channel count and the
/// channel names.
pub fn create_image(name: &str, width: u32, height: u32) -> Vec<u8> {
    packet(CREATE_IMAGE, |b| {
        b.push(1);
        string(b, name);
        int32(b, width);
        int32(b, height);
        int32(b, CHANNELS.len() as u32);
        CHANNELS.iter().for_each(|c| string(b, c));
    })
}

/// UpdateImage V3 of the `width` × `height` pixels at (`x`, `y`) of the image `name`: grab
/// focus (here: no), the name, the channel count, the channel names, x, y, width, height,
/// each channel's offset (`int64`) and stride (`int64`) into the data, then the data, f32;
/// `rgb` holds R, G, B of each pixel, row by row.
pub fn update_image(name: &str, x: u32, y: u32, width: u32, height: u32, rgb: &[f32]) -> Vec<u8> {
    debug_assert_eq!(rgb.len(), 3 * width as usize * height as usize);
    packet(UPDATE_IMAGE_V3, |b| {
        b.push(0);
        string(b, name);
        int32(b, CHANNELS.len() as u32);
        CHANNELS.iter().for_each(|c| string(b, c));
        [x, y, width, height].into_iter().for_each(|v| int32(b, v));
        (0..CHANNELS.len() as i64).for_each(|c| b.extend_from_slice(&c.to_le_bytes()));
        CHANNELS
            .iter()
            .for_each(|_| b.extend_from_slice(&(CHANNELS.len() as i64).to_le_bytes()));
        b.reserve(4 * rgb.len());
        rgb.iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
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
        assert_eq!(create_image("a.exr", 2, 1), expected);
        // Sizes go out as they are, low byte first.
        let big = create_image("", 70_000, 0x0102_0304);
        assert_eq!(&big[7..15], &[0x70, 0x11, 0x01, 0, 4, 3, 2, 1]);
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
        assert_eq!(update_image("a", 3, 258, 2, 1, &rgb), expected);
    }
}
