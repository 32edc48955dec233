//! A 5×7 bitmap font for legend labels (digits, sign, point, exponent and a few
//! letters), so pictures carry their numbers without a font file or system fonts.

use asperity_core::RgbaImage;

const GLYPHS: &[(char, [u8; 7])] = &[
    ('0', [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E]),
    ('1', [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E]),
    ('2', [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F]),
    ('3', [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E]),
    ('4', [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02]),
    ('5', [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E]),
    ('6', [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E]),
    ('7', [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08]),
    ('8', [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E]),
    ('9', [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C]),
    ('.', [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C]),
    ('-', [0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00]),
    ('+', [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00]),
    ('e', [0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E]),
    ('z', [0x00, 0x00, 0x1F, 0x02, 0x04, 0x08, 0x1F]),
    ('=', [0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00]),
    (' ', [0; 7]),
];

/// Width in pixels of `text` at `scale`.
pub fn text_width(text: &str, scale: u32) -> u32 {
    text.chars().count() as u32 * 6 * scale
}

/// Draws `text` with its top-left corner at (x, y); unknown characters are blank.
pub fn draw_text(img: &mut RgbaImage, x: u32, y: u32, text: &str, scale: u32, rgba: [u8; 4]) {
    for (k, ch) in text.chars().enumerate() {
        let Some((_, rows)) = GLYPHS.iter().find(|(c, _)| *c == ch) else {
            continue;
        };
        for (ry, bits) in rows.iter().enumerate() {
            for rx in 0..5 {
                if bits & (0x10 >> rx) == 0 {
                    continue;
                }
                for sy in 0..scale {
                    for sx in 0..scale {
                        let px = x + (k as u32 * 6 + rx) * scale + sx;
                        let py = y + ry as u32 * scale + sy;
                        if px < img.width() && py < img.height() {
                            img.put(px, py, rgba);
                        }
                    }
                }
            }
        }
    }
}

/// A short label for a number: 4 significant digits, scientific when needed.
pub fn format_number(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_and_formats() {
        let mut img = RgbaImage::filled(40, 10, [0, 0, 0, 255]);
        draw_text(&mut img, 1, 1, "1.5", 1, [255, 255, 255, 255]);
        let lit = img.pixels().chunks(4).filter(|p| p[0] == 255).count();
        assert!(lit > 10);
        assert_eq!(format_number(0.25), "0.25");
        assert_eq!(format_number(-12.0), "-12");
        assert_eq!(format_number(1.5e-7), "1.500e-7");
        assert_eq!(text_width("abc", 2), 36);
    }
}
