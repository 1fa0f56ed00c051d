//! The legend laid out for a frame's height and rasterized on the CPU: a light
//! panel (legible on white and on the black isolation background) holding the title
//! and either a colour bar with a thin dark border, tick marks and labels, or a
//! swatch per code. Text is the Hack font that egui bundles (MIT and Bitstream Vera
//! licences, through `epaint_default_fonts`), drawn with `ab_glyph`.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use strata_render::image::{Rgba, RgbaImage};
use strata_render::overlay_origin;

use super::{Entries, Legend};
use crate::{Error, Result};

const TEXT: [u8; 3] = [24, 24, 24];
const BORDER: [u8; 3] = [40, 40, 40];
const PANEL: [u8; 4] = [255, 255, 255, 235];

/// Where a legend's parts lie in its image, in pixels; the image sits at the
/// frame's right edge, vertically centred ([`Layout::origin`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The image's width and height.
    pub size: [u32; 2],
    /// Font size in pixels.
    pub font: f32,
    /// The colour bar inside its border, `[x0, y0, x1, y1)`: the high end at the top.
    pub bar: Option<[u32; 4]>,
    /// Each tick's row, and whether it is labelled: a label closer than a line to
    /// one already placed (the range's ends first) is left out, its mark kept.
    pub ticks: Vec<(u32, bool)>,
    /// Each code's swatch inside its border, as `bar`, top to bottom.
    pub swatches: Vec<[u32; 4]>,
    /// The codes listed (the others are counted in a last line).
    pub listed: usize,
}

impl Layout {
    /// The image's top-left pixel in a frame of `width` x `height` (it may lie
    /// outside a frame smaller than the image): where the renderer draws it.
    pub fn origin(&self, width: u32, height: u32) -> [i64; 2] {
        overlay_origin((width, height), (self.size[0], self.size[1]))
    }
}

/// The bundled font.
fn font() -> Result<FontRef<'static>> {
    FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR)
        .map_err(|e| Error::scene(format!("the legend's font: {e}")))
}

impl Legend {
    /// How this legend is laid out on a frame `height` pixels high: text a
    /// fifty-second of the height (15 px at 800), the bar 40 % of it.
    pub fn layout(&self, height: u32) -> Result<Layout> {
        let font = font()?;
        let s = (height as f32 / 52.0).clamp(11.0, 28.0).round();
        let scaled = font.as_scaled(PxScale::from(s));
        let width_of = |text: &str| text_width(&scaled, text).ceil() as u32;
        let unit = |f: f32| (f * s).round() as u32;
        let (pad, margin, title_h) = (unit(0.7), unit(0.8), unit(1.3));
        let title_w = width_of(&self.title());
        let mut rows = Vec::new();
        let (body_w, body_h, bar, swatches, listed) = match &self.entries {
            Entries::Ticks(ticks) => {
                let labels = ticks.iter().map(|t| width_of(&t.label)).max().unwrap_or(0);
                let (bar_w, tick, gap) = (unit(1.1), unit(0.4), unit(0.3));
                let bar_h = ((0.4 * height as f32) as u32).max(unit(3.0));
                // Half a label's height above and below, for the end labels.
                let top = pad + title_h + unit(0.6);
                let bar = [pad + 1, top + 1, pad + 1 + bar_w, top + 1 + bar_h];
                rows = tick_rows(ticks.iter().map(|t| t.fraction), bar, 1.15 * s);
                let w = bar_w + 2 + tick + gap + labels;
                (w, bar_h + 2 + unit(1.2), Some(bar), Vec::new(), 0)
            }
            Entries::Codes(codes) => {
                let row = unit(1.5);
                let rows = ((0.8 * height as f32) as u32 / row.max(1)).max(2) as usize;
                let listed = if codes.len() > rows {
                    rows - 1
                } else {
                    codes.len()
                };
                let labels = codes.iter().take(listed).map(|c| width_of(&code_label(c)));
                let more = width_of(&more_label(codes.len() - listed));
                let labels = labels.max().unwrap_or(0).max(more);
                let top = pad + title_h;
                let box_s = unit(1.0);
                let swatches = (0..listed as u32)
                    .map(|r| {
                        let y = top + r * row + (row - box_s) / 2;
                        [pad + 1, y + 1, pad + box_s - 1, y + box_s - 1]
                    })
                    .collect();
                let lines = listed + usize::from(listed < codes.len());
                let w = box_s + unit(0.5) + labels;
                (w, lines as u32 * row, None, swatches, listed)
            }
        };
        let panel_w = pad + title_w.max(body_w) + pad;
        Ok(Layout {
            size: [panel_w + margin, pad + title_h + body_h + pad],
            font: s,
            bar,
            ticks: rows,
            swatches,
            listed,
        })
    }

    /// The legend drawn for a frame `height` pixels high, RGBA8 with straight alpha
    /// (transparent around the panel), to blend over the frame's right edge.
    pub fn image(&self, height: u32) -> Result<RgbaImage> {
        let layout = self.layout(height)?;
        let font = font()?;
        let scaled = font.as_scaled(PxScale::from(layout.font));
        let s = layout.font;
        let unit = |f: f32| (f * s).round() as u32;
        let [w, h] = layout.size;
        let mut image = RgbaImage::new(w, h);
        let (pad, margin) = (unit(0.7), unit(0.8));
        fill(&mut image, [0, 0, w - margin, h], PANEL);
        frame_rect(&mut image, [0, 0, w - margin, h], [0, 0, 0, 70]);
        let ascent = scaled.ascent();
        let title_base = pad as f32 + ascent;
        draw_text(&mut image, &scaled, &self.title(), (pad as f32, title_base));
        match (&self.entries, layout.bar) {
            (Entries::Ticks(ticks), Some(bar)) => {
                draw_bar(&mut image, bar, &self.colormap.table());
                let x1 = bar[2];
                let (tick, gap) = (unit(0.4), unit(0.3));
                let middle = ascent * 0.36;
                for (t, &(y, labelled)) in ticks.iter().zip(&layout.ticks) {
                    let rgba = [BORDER[0], BORDER[1], BORDER[2], 255];
                    fill(&mut image, [x1 + 1, y, x1 + 1 + tick, y + 1], rgba);
                    if labelled {
                        let x = (x1 + 1 + tick + gap) as f32;
                        draw_text(&mut image, &scaled, &t.label, (x, y as f32 + middle));
                    }
                }
            }
            (Entries::Codes(codes), _) => {
                let row = unit(1.5) as f32;
                for (c, sw) in codes.iter().zip(&layout.swatches) {
                    let [r, g, b] = c.colour;
                    fill(&mut image, *sw, [r, g, b, 255]);
                    let outer = [sw[0] - 1, sw[1] - 1, sw[2] + 1, sw[3] + 1];
                    frame_rect(&mut image, outer, [BORDER[0], BORDER[1], BORDER[2], 255]);
                    let base = (sw[1] + sw[3]) as f32 / 2.0 + ascent * 0.36;
                    let x = (sw[2] + 1 + unit(0.5)) as f32;
                    draw_text(&mut image, &scaled, &code_label(c), (x, base.round()));
                }
                if layout.listed < codes.len() {
                    let y = layout.swatches.last().map_or(pad as f32, |sw| sw[3] as f32);
                    let label = more_label(codes.len() - layout.listed);
                    draw_text(&mut image, &scaled, &label, (pad as f32, y + row * 0.9));
                }
            }
            _ => {}
        }
        Ok(image)
    }
}

/// The rows of ticks at `fractions` along `bar` (high end at the top), each with
/// whether it is labelled: not when its label would come within `line` pixels of
/// one placed before, the first and last (the range's ends) placed first.
fn tick_rows(fractions: impl Iterator<Item = f64>, bar: [u32; 4], line: f32) -> Vec<(u32, bool)> {
    let [_, y0, _, y1] = bar;
    let rows: Vec<u32> = fractions
        .map(|f| {
            let y = f64::from(y1 - 1) - f.clamp(0.0, 1.0) * f64::from(y1 - y0 - 1);
            y.round() as u32
        })
        .collect();
    let n = rows.len();
    let order = [0, n.saturating_sub(1)]
        .into_iter()
        .chain(1..n.saturating_sub(1));
    let mut placed: Vec<u32> = Vec::new();
    let mut labelled = vec![false; n];
    for i in order.filter(|&i| i < n) {
        if placed.iter().all(|&p| p.abs_diff(rows[i]) as f32 >= line) {
            placed.push(rows[i]);
            labelled[i] = true;
        }
    }
    rows.into_iter().zip(labelled).collect()
}

/// A code as listed: the code, and its name where it has one.
fn code_label(code: &super::Code) -> String {
    match &code.name {
        Some(name) => format!("{} {name}", code.code),
        None => code.code.to_string(),
    }
}

fn more_label(more: usize) -> String {
    format!("... {more} more")
}

/// The colour map from its high end at the top to its low end at the bottom, in a
/// one-pixel dark border around `[x0, y0, x1, y1)`.
fn draw_bar(image: &mut RgbaImage, [x0, y0, x1, y1]: [u32; 4], table: &[u8]) {
    let rows = (y1 - y0).max(2);
    for y in y0..y1 {
        let t = 1.0 - f64::from(y - y0) / f64::from(rows - 1);
        let i = 4 * ((t * 255.0).round() as usize).min(255);
        fill(
            image,
            [x0, y, x1, y + 1],
            [table[i], table[i + 1], table[i + 2], 255],
        );
    }
    let border = [BORDER[0], BORDER[1], BORDER[2], 255];
    frame_rect(image, [x0 - 1, y0 - 1, x1 + 1, y1 + 1], border);
}

/// The width of `text` in pixels.
fn text_width<F: Font>(font: &impl ScaleFont<F>, text: &str) -> f32 {
    let mut prev = None;
    let mut width = 0.0;
    for c in text.chars() {
        let id = font.glyph_id(c);
        width += prev.map_or(0.0, |p| font.kern(p, id)) + font.h_advance(id);
        prev = Some(id);
    }
    width
}

/// Draws `text` with its baseline starting at `(x, y)`.
fn draw_text<F: Font>(
    image: &mut RgbaImage,
    font: &impl ScaleFont<F>,
    text: &str,
    (x, y): (f32, f32),
) {
    let mut caret = x.round();
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        caret += prev.map_or(0.0, |p| font.kern(p, id));
        prev = Some(id);
        let glyph = id.with_scale_and_position(font.scale(), point(caret, y.round()));
        caret += font.h_advance(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let px = bounds.min.x as i64 + i64::from(gx);
            let py = bounds.min.y as i64 + i64::from(gy);
            if let (Ok(px), Ok(py)) = (u32::try_from(px), u32::try_from(py))
                && px < image.width()
                && py < image.height()
            {
                let a = (coverage.clamp(0.0, 1.0) * 255.0).round() as u8;
                over(image.get_pixel_mut(px, py), [TEXT[0], TEXT[1], TEXT[2], a]);
            }
        });
    }
}

/// Blends `rgba` (straight alpha) over the rectangle `[x0, y0, x1, y1)`.
fn fill(image: &mut RgbaImage, [x0, y0, x1, y1]: [u32; 4], rgba: [u8; 4]) {
    for y in y0..y1.min(image.height()) {
        for x in x0..x1.min(image.width()) {
            over(image.get_pixel_mut(x, y), rgba);
        }
    }
}

/// Blends a one-pixel outline of `[x0, y0, x1, y1)` in `rgba`.
fn frame_rect(image: &mut RgbaImage, [x0, y0, x1, y1]: [u32; 4], rgba: [u8; 4]) {
    fill(image, [x0, y0, x1, y0 + 1], rgba);
    fill(image, [x0, y1 - 1, x1, y1], rgba);
    fill(image, [x0, y0 + 1, x0 + 1, y1 - 1], rgba);
    fill(image, [x1 - 1, y0 + 1, x1, y1 - 1], rgba);
}

/// `src` (straight alpha) over `dst`, in place.
fn over(dst: &mut Rgba<u8>, src: [u8; 4]) {
    let sa = f32::from(src[3]) / 255.0;
    let da = f32::from(dst.0[3]) / 255.0;
    let out = sa + da * (1.0 - sa);
    if out <= 0.0 {
        return;
    }
    for (d, s) in dst.0.iter_mut().zip(src).take(3) {
        let v = (f32::from(s) * sa + f32::from(*d) * da * (1.0 - sa)) / out;
        *d = v.round() as u8;
    }
    dst.0[3] = (out * 255.0).round() as u8;
}
