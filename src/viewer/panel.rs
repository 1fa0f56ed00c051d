//! The side panel: every field of the scene a window edits, what the model holds,
//! the picked cell, the frame's statistics and the last error.

use egui::{ComboBox, DragValue, Slider, Ui};
use strata_render::{Colormap, WireMode};

use super::stats::FrameStat;
use crate::cell::CellInfo;
use crate::engine::Pick;
use crate::scene::{Attenuate, GridLineSpec, IsolineSpec, Lod, Scene};

/// What the panel shows of the model (read once it is open).
#[derive(Clone, Debug, Default)]
pub struct Facts {
    /// Cells along I, J, K.
    pub dims: Option<[usize; 3]>,
    /// Static properties, then the report steps' arrays.
    pub properties: Vec<String>,
    /// Report steps: number and date.
    pub steps: Vec<(i32, Option<String>)>,
}

/// The panel's own state between frames.
#[derive(Default)]
pub struct PanelState {
    /// The scene file the save and load buttons use.
    pub scene_file: String,
    /// The screenshot file and size (empty: the window's).
    pub shot_file: String,
    /// The screenshot size, `WIDTHxHEIGHT`, or empty for the window's.
    pub shot_size: String,
    /// Report steps advance by themselves.
    pub playing: bool,
    /// The cell picked last, with its corners and values when the model is open.
    pub picked: Option<(Pick, Option<CellInfo>)>,
    /// The last error, shown until the next good frame.
    pub error: Option<String>,
    /// Something done, in words (a file written).
    pub message: Option<String>,
}

/// What the panel asks the window to do besides editing the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Request {
    /// Write the scene as JSON to the file named.
    SaveScene,
    /// Read the scene from the file named.
    LoadScene,
    /// Write a screenshot.
    Screenshot,
}

/// Shows the panel, editing `scene`; returns what else was asked.
pub fn show(
    ui: &mut Ui,
    scene: &mut Scene,
    facts: &Facts,
    state: &mut PanelState,
    stat: Option<&FrameStat>,
    building: Option<f32>,
) -> Vec<Request> {
    let mut requests = Vec::new();
    egui::ScrollArea::vertical().show(ui, |ui| {
        if let Some(fraction) = building {
            ui.add(
                egui::ProgressBar::new(fraction)
                    .text(format!("building the hierarchy: {:.0} %", 100.0 * fraction)),
            );
        }
        if let Some(error) = &state.error {
            ui.colored_label(egui::Color32::from_rgb(200, 30, 30), error);
        }
        if let Some(message) = &state.message {
            ui.label(message);
        }
        cells(ui, scene, facts);
        colours(ui, scene, facts, state);
        lines(ui, scene, facts);
        files(ui, state, &mut requests);
        if let Some((pick, info)) = &state.picked {
            egui::CollapsingHeader::new("Picked cell")
                .default_open(true)
                .show(ui, |ui| {
                    let [i, j, k] = pick.cell.map(|c| c + 1);
                    let [x, y, depth] = pick.point;
                    ui.label(format!(
                        "cell {i},{j},{k} at x {x:.1}, y {y:.1}, depth {depth:.2}"
                    ));
                    if let Some(info) = info {
                        picked_cell(ui, info);
                    }
                });
        }
        if let Some(stat) = stat {
            ui.separator();
            ui.label(format!("{}\n{}", stat.line(), stat.drawn));
        }
    });
    requests
}

/// An optional 1-based inclusive range over `1..=n`, edited as a checkbox and two
/// numbers; unbounded above while `n` is not known (the engine refuses a range past
/// the model's end, and names it).
fn range(ui: &mut Ui, label: &str, value: &mut Option<[usize; 2]>, n: Option<usize>) {
    let (n, whole) = match n {
        Some(n) => (n.max(1), n.max(1)),
        None => (usize::MAX, 1),
    };
    ui.horizontal(|ui| {
        let mut on = value.is_some();
        ui.checkbox(&mut on, label);
        match (on, value.as_mut()) {
            (true, Some([lo, hi])) => {
                ui.add(DragValue::new(lo).range(1..=n));
                ui.add(DragValue::new(hi).range(1..=n));
                *hi = (*hi).max(*lo);
            }
            (true, None) => *value = Some([1, whole]),
            (false, _) => *value = None,
        }
    });
}

fn cells(ui: &mut Ui, scene: &mut Scene, facts: &Facts) {
    egui::CollapsingHeader::new("Cells")
        .default_open(true)
        .show(ui, |ui| {
            let dims = facts.dims;
            range(ui, "layers K", &mut scene.layers, dims.map(|d| d[2]));
            range(ui, "columns I", &mut scene.i, dims.map(|d| d[0]));
            range(ui, "rows J", &mut scene.j, dims.map(|d| d[1]));
            ui.checkbox(&mut scene.inactive, "inactive cells");
            ui.checkbox(&mut scene.sides, "side walls");
            ui.horizontal(|ui| {
                ui.label("vertical exaggeration");
                ui.add(
                    DragValue::new(&mut scene.camera.z_scale)
                        .range(0.01..=100.0)
                        .speed(0.05),
                );
            });
            if let Lod::Hierarchy { pixels, .. } = &mut scene.lod {
                ui.horizontal(|ui| {
                    ui.label("LOD pixel error");
                    ui.add(DragValue::new(pixels).range(0.0..=64.0).speed(0.05));
                });
            }
        });
}

fn colours(ui: &mut Ui, scene: &mut Scene, facts: &Facts, state: &mut PanelState) {
    egui::CollapsingHeader::new("Colours")
        .default_open(true)
        .show(ui, |ui| {
            let colour = &mut scene.colour;
            ui.checkbox(&mut colour.solid, "solid colour");
            if !colour.solid {
                property_choice(ui, "property", &mut colour.property, facts);
            }
            if !facts.steps.is_empty() {
                let last = facts.steps.len() - 1;
                let mut at = colour
                    .step
                    .and_then(|s| facts.steps.iter().position(|(n, _)| *n == s))
                    .unwrap_or(last);
                let (number, date) = &facts.steps[at];
                ui.add(
                    Slider::new(&mut at, 0..=last)
                        .text(format!("step {number} {}", date.as_deref().unwrap_or(""))),
                );
                colour.step = Some(facts.steps[at].0);
                ui.checkbox(&mut state.playing, "play");
            }
            ComboBox::from_id_salt("colormap")
                .selected_text(colormap_name(colour.colormap))
                .show_ui(ui, |ui| {
                    for (name, map) in Colormap::ALL {
                        ui.selectable_value(&mut colour.colormap, map, name);
                    }
                });
            let mut typed = colour.range.is_some();
            ui.checkbox(&mut typed, "range typed (else the data's)");
            match (typed, colour.range.as_mut()) {
                (true, Some([lo, hi])) => {
                    ui.horizontal(|ui| {
                        ui.add(DragValue::new(lo).speed(0.01));
                        ui.add(DragValue::new(hi).speed(0.01));
                    });
                }
                (true, None) => colour.range = Some([0.0, 1.0]),
                (false, _) => colour.range = None,
            }
            ui.checkbox(&mut colour.smooth, "smooth between nodes");
        });
}

fn lines(ui: &mut Ui, scene: &mut Scene, facts: &Facts) {
    egui::CollapsingHeader::new("Lines")
        .default_open(true)
        .show(ui, |ui| {
            let wire = &mut scene.wire;
            ComboBox::from_id_salt("technique")
                .selected_text(wire.technique.name())
                .show_ui(ui, |ui| {
                    for mode in WireMode::ALL {
                        ui.selectable_value(&mut wire.technique, mode, mode.name());
                    }
                });
            ui.add(Slider::new(&mut wire.thickness, 0.5..=8.0).text("thickness px"));
            ui.horizontal(|ui| {
                ui.label("colour");
                ui.text_edit_singleline(&mut wire.color);
            });
            ComboBox::from_id_salt("attenuate")
                .selected_text(format!("attenuate: {:?}", wire.attenuate))
                .show_ui(ui, |ui| {
                    for a in [Attenuate::None, Attenuate::Intensity, Attenuate::Thickness] {
                        ui.selectable_value(&mut wire.attenuate, a, format!("{a:?}"));
                    }
                });
            let mut iso = scene.isolines.is_some();
            ui.checkbox(&mut iso, "isolines");
            match (iso, scene.isolines.as_mut()) {
                (true, Some(spec)) => isolines(ui, spec, facts),
                (true, None) => {
                    let first = scene
                        .colour
                        .property
                        .clone()
                        .or_else(|| facts.properties.first().cloned());
                    scene.isolines = Some(IsolineSpec::of(first.as_deref()));
                }
                (false, _) => scene.isolines = None,
            }
            let mut grid = scene.grid_lines.is_some();
            ui.checkbox(&mut grid, "map grid lines");
            match (grid, scene.grid_lines.as_mut()) {
                (true, Some(spec)) => {
                    ui.horizontal(|ui| {
                        ui.label("spacing");
                        ui.add(DragValue::new(&mut spec.spacing).range(1.0..=1e6));
                        ui.label("origin");
                        ui.add(DragValue::new(&mut spec.origin[0]));
                        ui.add(DragValue::new(&mut spec.origin[1]));
                    });
                }
                (true, None) => {
                    scene.grid_lines = Some(GridLineSpec {
                        spacing: 500.0,
                        origin: [0.0, 0.0],
                    });
                }
                (false, _) => scene.grid_lines = None,
            }
        });
}

fn isolines(ui: &mut Ui, spec: &mut IsolineSpec, facts: &Facts) {
    property_choice(ui, "isoline property", &mut spec.property, facts);
    ui.horizontal(|ui| {
        let mut spacing = spec.spacing.unwrap_or(0.0);
        ui.label("spacing (0: about ten lines)");
        ui.add(DragValue::new(&mut spacing).range(0.0..=1e9).speed(0.01));
        spec.spacing = (spacing > 0.0).then_some(spacing);
    });
    ui.horizontal(|ui| {
        ui.label("major every");
        ui.add(DragValue::new(&mut spec.major_every).range(1..=100));
    });
}

fn property_choice(ui: &mut Ui, label: &str, property: &mut Option<String>, facts: &Facts) {
    let shown = property.clone().unwrap_or_else(|| "(default)".into());
    ComboBox::from_id_salt(label)
        .selected_text(format!("{label}: {shown}"))
        .show_ui(ui, |ui| {
            for name in &facts.properties {
                ui.selectable_value(property, Some(name.clone()), name);
            }
        });
}

fn files(ui: &mut Ui, state: &mut PanelState, requests: &mut Vec<Request>) {
    egui::CollapsingHeader::new("Files")
        .default_open(false)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.text_edit_singleline(&mut state.scene_file);
                if ui.button("save scene").clicked() {
                    requests.push(Request::SaveScene);
                }
                if ui.button("load scene").clicked() {
                    requests.push(Request::LoadScene);
                }
            });
            ui.horizontal(|ui| {
                ui.text_edit_singleline(&mut state.shot_file);
                ui.add(
                    egui::TextEdit::singleline(&mut state.shot_size)
                        .hint_text("WxH")
                        .desired_width(80.0),
                );
                if ui.button("screenshot").clicked() {
                    requests.push(Request::Screenshot);
                }
            });
        });
}

fn picked_cell(ui: &mut Ui, cell: &CellInfo) {
    ui.label(if cell.active { "active" } else { "inactive" });
    let depths: Vec<String> = cell
        .corners
        .iter()
        .map(|c| format!("{:.2}", c[2]))
        .collect();
    ui.label(format!("corner depths {}", depths.join(" ")));
    for (name, value) in &cell.values {
        match value {
            Some(v) => ui.label(format!("{name} = {v}")),
            None => ui.label(format!("{name} undefined")),
        };
    }
}

fn colormap_name(map: Colormap) -> &'static str {
    Colormap::ALL
        .iter()
        .find(|(_, m)| *m == map)
        .map_or("?", |(name, _)| name)
}
