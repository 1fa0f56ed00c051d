//! Measurements of rendered pictures that tests and benchmarks share: which pixels
//! are line pixels, and how well one picture's lines match another's.

/// Line mask of an isolation frame: pixels the lines cover at least half of.
pub fn line_mask(image: &[u8], line_luma: f64) -> Vec<bool> {
    image
        .chunks_exact(4)
        .map(|p| {
            let luma = 0.299 * f64::from(p[0]) + 0.587 * f64::from(p[1]) + 0.114 * f64::from(p[2]);
            luma >= 0.5 * line_luma
        })
        .collect()
}

/// Pixels of `a` within `tol` pixels (Chebyshev) of a pixel of `b`, both masks of
/// frames `width` pixels wide.
fn matched(a: &[bool], b: &[bool], width: usize, tol: i64) -> usize {
    let w = width.max(1) as i64;
    let h = a.len().min(b.len()) as i64 / w;
    (0..h)
        .map(|y| {
            (0..w)
                .filter(|&x| {
                    a[(y * w + x) as usize]
                        && (-tol..=tol).any(|dy| {
                            (-tol..=tol).any(|dx| {
                                let (xx, yy) = (x + dx, y + dy);
                                xx >= 0 && yy >= 0 && xx < w && yy < h && b[(yy * w + xx) as usize]
                            })
                        })
                })
                .count()
        })
        .sum()
}

/// Precision, recall and F1 of the line pixels `got` against `want` (masks of frames
/// `width` pixels wide), a pixel matching one of the other within `tol` pixels.
pub fn f1(got: &[bool], want: &[bool], width: usize, tol: i64) -> (f64, f64, f64) {
    let (ng, nw) = (
        got.iter().filter(|&&p| p).count(),
        want.iter().filter(|&&p| p).count(),
    );
    if ng == 0 || nw == 0 {
        return (0.0, 0.0, if ng == nw { 1.0 } else { 0.0 });
    }
    let precision = matched(got, want, width, tol) as f64 / ng as f64;
    let recall = matched(want, got, width, tol) as f64 / nw as f64;
    let f = if precision + recall > 0.0 {
        2.0 * precision * recall / (precision + recall)
    } else {
        0.0
    };
    (precision, recall, f)
}

#[cfg(test)]
mod tests {
    use super::*;

    const WIDTH: u32 = 1000;
    const HEIGHT: u32 = 800;

    fn frame(lines: &[(u32, u32)]) -> Vec<bool> {
        let mut f = vec![false; (WIDTH * HEIGHT) as usize];
        for &(x, y) in lines {
            f[(y * WIDTH + x) as usize] = true;
        }
        f
    }

    #[test]
    fn f1_matches_lines_within_the_tolerance() {
        let want = frame(&(100..200).map(|x| (x, 50)).collect::<Vec<_>>());
        let moved = frame(&(100..200).map(|x| (x, 51)).collect::<Vec<_>>());
        let w = WIDTH as usize;
        assert_eq!(f1(&want, &want, w, 0), (1.0, 1.0, 1.0));
        // One pixel off: all matched within one pixel, none exactly.
        assert_eq!(f1(&moved, &want, w, 1).2, 1.0);
        assert_eq!(f1(&moved, &want, w, 0).2, 0.0);
        // Half the line missing: precision 1, recall 1/2.
        let half = frame(&(100..150).map(|x| (x, 50)).collect::<Vec<_>>());
        let (p, r, f) = f1(&half, &want, w, 1);
        assert!((p - 1.0).abs() < 1e-12 && (r - 0.5).abs() < 0.02 && (f - 2.0 / 3.0).abs() < 0.02);
    }

    #[test]
    fn line_pixels_are_those_half_covered() {
        // Solid colour luma 200: a pixel at 120 is a line pixel, one at 80 is not.
        let image = [120u8, 120, 120, 255, 80, 80, 80, 255];
        assert_eq!(line_mask(&image, 200.0), vec![true, false]);
    }
}
