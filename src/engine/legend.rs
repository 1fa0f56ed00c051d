//! The legend a scene's frames show: worked out from the content's colouring before
//! each frame, the scale checked against the values, and handed to the renderer as
//! its overlay only when what it says or the frame's height changed.

use strata_render::image::RgbaImage;
use strata_render::{Renderer, Scale, overlay_origin};

use super::{Content, Model};
use crate::legend::{Legend, UnitSystem, codes_of, unit};
use crate::scene::Scene;
use crate::surfaces::colour_values_of;
use crate::{Error, Result};

/// What the renderer's overlay shows, and the codes of a categorical property.
#[derive(Default)]
pub struct Shown {
    /// The legend drawn and the frame height it was drawn for (`Some(None)`: no
    /// overlay); `None` until the first frame sets the renderer's.
    legend: Option<Option<(Legend, u32)>>,
    /// The size of the legend's image, while one is shown.
    size: Option<[u32; 2]>,
    /// The codes present in content number `.0` (the engine's count of contents
    /// built), read once per content.
    codes: Option<(usize, Vec<i64>)>,
}

impl Shown {
    /// Checks that `scene`'s scale suits the values `content` colours by, and shows
    /// the legend the scene asks for (or none) on `renderer`; `built` numbers the
    /// content.
    pub fn update(
        &mut self,
        scene: &Scene,
        (content, built): (&Content, usize),
        model: Option<&Model>,
        renderer: &mut Renderer,
    ) -> Result<()> {
        let want = self
            .legend_of(scene, (content, built), model)?
            .filter(|_| scene.legend)
            .map(|legend| (legend, scene.size[1]));
        if self.legend.as_ref() != Some(&want) {
            let image = want.as_ref().map(|(l, h)| l.image(*h)).transpose()?;
            renderer.set_overlay(image.as_ref());
            self.size = image.map(|i| [i.width(), i.height()]);
            self.legend = Some(want);
        }
        Ok(())
    }

    /// The pixels `[x0, y0, x1, y1)` the legend covers in `frame`, if one is shown:
    /// at the right edge, vertically centred, as the renderer places it.
    pub fn area(&self, frame: &RgbaImage) -> Option<[i64; 4]> {
        let [w, h] = self.size?;
        let [x, y] = overlay_origin(frame.dimensions(), (w, h));
        Some([x, y, x + i64::from(w), y + i64::from(h)])
    }

    /// The legend of the property colouring `content` as `scene` maps it; `None`
    /// for a solid colour. A log scale over values not all positive, or a
    /// categorical one over values that are not codes, is refused.
    fn legend_of(
        &mut self,
        scene: &Scene,
        (content, built): (&Content, usize),
        model: Option<&Model>,
    ) -> Result<Option<Legend>> {
        let colouring = match content {
            Content::Whole(whole) => whole.colouring(),
            Content::Parts(parts) => parts.colouring(),
            Content::Hierarchy(h) => h.scalar_range().map(|r| ("stored property".into(), r)),
        };
        let Some((property, data)) = colouring else {
            return Ok(None);
        };
        let colour = &scene.colour;
        let range = colour.range.map_or(data, |[lo, hi]| (lo, hi));
        if colour.scale == Scale::Log && range.0 <= 0.0 {
            return Err(Error::scene(format!(
                "colour: a log scale needs positive values, and {property} spans {} .. {} over \
                 the drawn cells: give --range LO,HI with LO above 0, or --scale linear",
                data.0, data.1
            )));
        }
        let codes = match colour.scale {
            Scale::Categorical => self.codes(&property, (content, built), model)?,
            Scale::Linear | Scale::Log => &[],
        };
        let unit = model.and_then(|m| unit(&property, UnitSystem::from(m.grid.units)));
        let map = (colour.colormap, colour.scale);
        Ok(Some(Legend::new(&property, unit, map, range, codes)))
    }

    /// The codes of `property` in content number `built`, read on first use.
    fn codes(
        &mut self,
        property: &str,
        (content, built): (&Content, usize),
        model: Option<&Model>,
    ) -> Result<&[i64]> {
        if self.codes.as_ref().is_none_or(|(n, _)| *n != built) {
            let of_model = |options| -> Result<Vec<i64>> {
                let model = model.ok_or_else(|| Error::scene("scene: no model"))?;
                let values = colour_values_of(&model.grid, options)?;
                codes_of(property, values.into_iter().flatten())
            };
            let codes = match content {
                Content::Whole(whole) => of_model(whole.options())?,
                Content::Parts(parts) => of_model(parts.options())?,
                Content::Hierarchy(h) => codes_of(property, h.values())?,
            };
            self.codes = Some((built, codes));
        }
        Ok(self.codes.as_ref().map_or(&[], |(_, c)| c.as_slice()))
    }
}
