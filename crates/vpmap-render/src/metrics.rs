//! Text widths for laying out SVG text without loading fonts.
//!
//! Advance widths of DejaVu Sans (Book and Bold, version 2.37), in 1/2048 em, read from the
//! fonts' `hmtx` tables for printable ASCII and the few symbols the floor plan uses. Other
//! characters count as 1 em, wider than most glyphs, so estimates err on the wide side.
//! Kerning only narrows text, so these widths are upper bounds for DejaVu Sans.

/// Units per em of DejaVu Sans.
const UNITS_PER_EM: f64 = 2048.0;

/// Advances of `' '..='~'`, DejaVu Sans Book.
const BOOK_ASCII: [u16; 95] = [
    651, 821, 942, 1716, 1303, 1946, 1597, 563, 799, 799, 1024, 1716, 651, 739, 651, 690, 1303,
    1303, 1303, 1303, 1303, 1303, 1303, 1303, 1303, 1303, 690, 690, 1716, 1716, 1716, 1087, 2048,
    1401, 1405, 1430, 1577, 1294, 1178, 1587, 1540, 604, 604, 1343, 1141, 1767, 1532, 1612, 1235,
    1612, 1423, 1300, 1251, 1499, 1401, 2025, 1403, 1251, 1403, 799, 690, 799, 1716, 1024, 1024,
    1255, 1300, 1126, 1300, 1260, 721, 1300, 1298, 569, 569, 1186, 569, 1995, 1298, 1253, 1300,
    1300, 842, 1067, 803, 1298, 1212, 1675, 1212, 1212, 1075, 1303, 690, 1303, 1716,
];

/// Advances of `' '..='~'`, DejaVu Sans Bold.
const BOLD_ASCII: [u16; 95] = [
    713, 934, 1067, 1716, 1425, 2052, 1786, 627, 936, 936, 1071, 1716, 778, 850, 778, 748, 1425,
    1425, 1425, 1425, 1425, 1425, 1425, 1425, 1425, 1425, 819, 819, 1716, 1716, 1716, 1188, 2048,
    1585, 1561, 1503, 1700, 1399, 1399, 1681, 1714, 762, 762, 1587, 1305, 2038, 1714, 1741, 1501,
    1741, 1577, 1475, 1397, 1663, 1585, 2259, 1579, 1483, 1485, 936, 748, 936, 1716, 1024, 1024,
    1382, 1466, 1214, 1466, 1389, 891, 1466, 1458, 702, 702, 1362, 702, 2134, 1458, 1407, 1466,
    1466, 1010, 1219, 979, 1458, 1335, 1892, 1321, 1335, 1192, 1458, 748, 1458, 1716,
];

/// Advance of one character, in 1/2048 em.
fn advance(c: char, bold: bool) -> u16 {
    let table = if bold { &BOLD_ASCII } else { &BOOK_ASCII };
    let ascii = u32::from(c)
        .checked_sub(0x20)
        .and_then(|i| table.get(i as usize));
    if let Some(a) = ascii {
        return *a;
    }
    match c {
        '°' => 1024,
        '×' | '→' => 1716,
        '²' => {
            if bold {
                897
            } else {
                821
            }
        }
        '·' => {
            if bold {
                778
            } else {
                651
            }
        }
        _ => 2048,
    }
}

/// Width of `text` set in DejaVu Sans at `font_px`, pixels (an upper bound).
#[must_use]
pub(crate) fn text_width_px(text: &str, font_px: f64, bold: bool) -> f64 {
    let units: u32 = text.chars().map(|c| u32::from(advance(c, bold))).sum();
    f64::from(units) / UNITS_PER_EM * font_px
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn widths_add_up_per_character() {
        // "W" is the widest Latin capital: 2025/2048 em in Book.
        assert_relative_eq!(text_width_px("W", 2048.0, false), 2025.0);
        assert_relative_eq!(text_width_px("iW", 2048.0, true), 702.0 + 2259.0);
        assert_relative_eq!(text_width_px("中", 10.0, false), 10.0);
        assert_relative_eq!(text_width_px("", 10.0, false), 0.0);
    }
}
