//! ROFF parameters (per-cell properties): continuous (`float`, `double`) or discrete
//! (`int`, `byte`, with code names), undefined values -999.0, -999 and 255, as xtgeo's
//! `RoffParameter` reads them.

use std::collections::BTreeMap;

use ndarray::Array3;

use super::model::reorder;
use super::tags::{Key, Place, Roff, Values};
use crate::{CornerPointGrid, Dims, Result};

/// Undefined values of ROFF parameters, by type.
const UNDEF_FLOAT: f32 = -999.0;
const UNDEF_INT: i32 = -999;
const UNDEF_BYTE: u8 = 255;

/// A parameter (per-cell property) in strata's cell order.
pub struct Parameter {
    /// Its name.
    pub name: String,
    /// One value per cell, `i` fastest, NaN where undefined.
    pub values: Vec<f32>,
    /// Code names of a discrete parameter that has them.
    pub codes: Option<BTreeMap<i32, String>>,
}

/// Adds a parameter to a grid, with its codes.
pub fn add(grid: &mut CornerPointGrid, p: Parameter, path: &std::path::Path) -> Result<()> {
    let d = grid.dims();
    let array = Array3::from_shape_vec((d.nz, d.ny, d.nx), p.values)
        .map_err(|e| crate::Error::model(path, &p.name, e.to_string()))?;
    grid.set_property(&p.name, array)
        .map_err(|e| crate::Error::model(path, &p.name, e.to_string()))?;
    let key = p.name.to_ascii_uppercase();
    match p.codes {
        Some(codes) => grid.codes.insert(key, codes),
        None => grid.codes.remove(&key),
    };
    Ok(())
}

/// Every `parameter` tag: name, data (float, double, int or byte) and, for a discrete
/// one, `codeNames`/`codeValues`.
pub fn parameters(place: &Place, roff: &Roff, d: Dims) -> Result<Vec<Parameter>> {
    let mut out = Vec::new();
    for (n, tag) in roff
        .tags
        .iter()
        .enumerate()
        .filter(|(_, t)| t.name == "parameter")
    {
        let no = n + 1;
        let err =
            |key: &Key, m: String| place.error(no, &format!("parameter/{}", key.name), key.at, m);
        let name = match tag.key("name").map(|k| (k, &k.values)) {
            Some((_, Values::Char(v))) if v.len() == 1 => v[0].clone(),
            Some((k, _)) => return Err(err(k, "expected one string".into())),
            None => {
                return Err(place.error(
                    no,
                    "parameter/name",
                    tag.at,
                    "a parameter without a name",
                ));
            }
        };
        let Some(data) = tag.key("data") else {
            return Err(place.error(
                no,
                "parameter/data",
                tag.at,
                format!("parameter {name} has no data"),
            ));
        };
        if data.values.len() != d.cell_count() {
            return Err(err(
                data,
                format!(
                    "{name}: {} values, the dimensions need {}",
                    data.values.len(),
                    d.cell_count()
                ),
            ));
        }
        let values: Vec<f32> = match &data.values {
            Values::Float(v) => v
                .iter()
                .map(|&x| if x == UNDEF_FLOAT { f32::NAN } else { x })
                .collect(),
            Values::Double(v) => v
                .iter()
                .map(|&x| {
                    if x == f64::from(UNDEF_FLOAT) {
                        f32::NAN
                    } else {
                        x as f32
                    }
                })
                .collect(),
            Values::Int(v) => v
                .iter()
                .map(|&x| if x == UNDEF_INT { f32::NAN } else { x as f32 })
                .collect(),
            Values::Byte(v) => v
                .iter()
                .map(|&x| {
                    if x == UNDEF_BYTE {
                        f32::NAN
                    } else {
                        f32::from(x)
                    }
                })
                .collect(),
            other => {
                return Err(err(
                    data,
                    format!("{name}: unexpected type {}", other.type_name()),
                ));
            }
        };
        let discrete = matches!(data.values, Values::Int(_) | Values::Byte(_));
        let codes = match (tag.key("codeNames"), tag.key("codeValues")) {
            (Some(names), Some(values)) if discrete => match (&names.values, &values.values) {
                (Values::Char(n), Values::Int(v)) if n.len() == v.len() => {
                    Some(v.iter().copied().zip(n.iter().cloned()).collect())
                }
                _ => {
                    return Err(err(
                        names,
                        format!("{name}: codeNames and codeValues differ in type or length"),
                    ));
                }
            },
            _ if discrete => Some(BTreeMap::new()),
            _ => None,
        };
        out.push(Parameter {
            values: reorder(d, &values, f32::NAN, |v| v),
            name,
            codes,
        });
    }
    Ok(out)
}
