//! Reading an X display's screenshot as `xwd -root` writes it (X Window Dump,
//! ZPixmap of 24 or 32 bits per pixel), so that tests can look at the display itself.

/// An RGB picture of the display.
pub struct Dump {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<[u8; 3]>,
}

fn field(bytes: &[u8], index: usize) -> u32 {
    let at = 4 * index;
    u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Reads `bytes` (an XWD file); panics with the reason on anything it does not know.
pub fn read(bytes: &[u8]) -> Dump {
    assert!(bytes.len() >= 100, "an XWD file of {} bytes", bytes.len());
    let header_size = field(bytes, 0) as usize;
    let (format, width, height) = (field(bytes, 2), field(bytes, 4), field(bytes, 5));
    let byte_order = field(bytes, 7);
    let (bits_per_pixel, bytes_per_line) = (field(bytes, 11), field(bytes, 12) as usize);
    let masks = [field(bytes, 14), field(bytes, 15), field(bytes, 16)];
    let colours = field(bytes, 19) as usize;
    assert_eq!(format, 2, "ZPixmap dumps only");
    assert!(
        bits_per_pixel == 32 || bits_per_pixel == 24,
        "{bits_per_pixel} bits per pixel"
    );
    let data = header_size + 12 * colours;
    let (width, height) = (width as usize, height as usize);
    let step = bits_per_pixel as usize / 8;
    assert!(
        bytes.len() >= data + bytes_per_line * height,
        "a truncated XWD file"
    );
    let mut rgb = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let at = data + y * bytes_per_line + x * step;
            let mut raw = [0u8; 4];
            raw[..step].copy_from_slice(&bytes[at..at + step]);
            let value = if byte_order == 0 {
                u32::from_le_bytes(raw)
            } else {
                u32::from_be_bytes(raw) >> (32 - bits_per_pixel)
            };
            rgb.push(masks.map(|m| ((value & m) >> m.trailing_zeros()) as u8));
        }
    }
    Dump { width, height, rgb }
}
