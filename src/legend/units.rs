//! The units Eclipse gives a property in each unit system, for the legend's title.

use strata_grid::Units;

/// An Eclipse unit system (RUNSPEC METRIC, FIELD or LAB; INTEHEAD item 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitSystem {
    /// METRIC: metres, bar, days.
    Metric,
    /// FIELD: feet, psia, days.
    Field,
    /// LAB: centimetres, atm, hours.
    Lab,
}

impl From<Units> for UnitSystem {
    /// The grid readers keep the unit system as the grid's length unit (METRIC and
    /// GRIDUNIT METRES read as metres, FIELD as feet, LAB as centimetres); a file
    /// that names none is METRIC, as it is to Eclipse.
    fn from(units: Units) -> Self {
        match units {
            Units::Metres => UnitSystem::Metric,
            Units::Feet => UnitSystem::Field,
            Units::Centimetres => UnitSystem::Lab,
        }
    }
}

/// The unit of `property` (any case) in `system`, as Eclipse writes it; `None`
/// where the property is a code or a count, or not known here.
pub fn unit(property: &str, system: UnitSystem) -> Option<&'static str> {
    let by_system = |metric, field, lab| {
        Some(match system {
            UnitSystem::Metric => metric,
            UnitSystem::Field => field,
            UnitSystem::Lab => lab,
        })
    };
    match property.to_ascii_uppercase().as_str() {
        "PERMX" | "PERMY" | "PERMZ" | "PERMR" | "PERMTHT" => Some("mD"),
        "PORO" | "NTG" | "SWAT" | "SOIL" | "SGAS" | "SWL" | "SWCR" | "SWU" | "SGL" | "SGCR"
        | "SGU" | "SOWCR" | "SOGCR" | "SWATINIT" => Some("fraction"),
        "PRESSURE" | "PRESS" | "PCW" | "PCG" | "PBUB" | "PDEW" => by_system("bar", "psia", "atm"),
        "DEPTH" | "TOPS" | "DX" | "DY" | "DZ" | "DZNET" => by_system("m", "ft", "cm"),
        "TEMP" => by_system("°C", "°F", "°C"),
        "PORV" => by_system("rm³", "rb", "rcc"),
        "TRANX" | "TRANY" | "TRANZ" => by_system("cP·rm³/day/bar", "cP·rb/day/psi", "cP·rcc/h/atm"),
        "RS" => by_system("sm³/sm³", "Mscf/stb", "scc/scc"),
        "RV" => by_system("sm³/sm³", "stb/Mscf", "scc/scc"),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_follow_the_unit_system() {
        use UnitSystem::{Field, Lab, Metric};
        assert_eq!(unit("PERMX", Field), Some("mD"));
        assert_eq!(unit("permz", Metric), Some("mD"));
        assert_eq!(unit("PORO", Lab), Some("fraction"));
        assert_eq!(unit("SWAT", Field), Some("fraction"));
        assert_eq!(unit("PRESSURE", Metric), Some("bar"));
        assert_eq!(unit("PRESSURE", Field), Some("psia"));
        assert_eq!(unit("PRESSURE", Lab), Some("atm"));
        assert_eq!(unit("DEPTH", Field), Some("ft"));
        assert_eq!(unit("TEMP", Metric), Some("°C"));
        assert_eq!(unit("FIPNUM", Metric), None);
        assert_eq!(unit("MYPROP", Field), None);
    }

    #[test]
    fn the_grid_units_name_the_system() {
        assert_eq!(UnitSystem::from(Units::Metres), UnitSystem::Metric);
        assert_eq!(UnitSystem::from(Units::Feet), UnitSystem::Field);
        assert_eq!(UnitSystem::from(Units::Centimetres), UnitSystem::Lab);
    }
}
