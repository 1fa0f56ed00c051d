//! Scripts: a window driven line by line, for tests and demos (`strata view
//! --script FILE`).
//!
//! One command per line; a line starting with `#` is a comment. The script starts once
//! the window has drawn two frames, its panel laid out:
//!
//! | command | what it does |
//! |---|---|
//! | `orbit DEGREES [FRAMES]` | turns the camera by DEGREES of azimuth over FRAMES frames (1) |
//! | `set FIELD JSON` | sets a scene field by its JSON path (`layers [1,3]`, `colour.property "PERMX"`, `isolines {"property":"PORO"}`, `isolines null`) |
//! | `frames N` | draws N frames with nothing changed |
//! | `pick X Y` | picks the cell at frame pixel (X, Y) and prints it as one JSON line |
//! | `wait` | waits until the hierarchy being built is done |
//! | `screenshot FILE [WxH]` | writes the frame (the window's size, or W x H) as PNG |
//! | `save FILE` / `load FILE` | writes or reads the scene as JSON |
//! | `quit` | closes the window |

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::{Error, Result, Scene};

/// One line of a script.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Turn the camera by `degrees` of azimuth over `frames` frames.
    Orbit {
        /// Degrees in all.
        degrees: f32,
        /// Frames to spread them over.
        frames: u32,
    },
    /// Set the scene field at `path` (dot-separated) to `value`.
    Set {
        /// The field's path, e.g. `colour.property`.
        path: String,
        /// Its new value.
        value: Value,
    },
    /// Draw frames with nothing changed.
    Frames(u32),
    /// Pick the cell at a pixel of the frame.
    Pick([f32; 2]),
    /// Wait for the hierarchy being built.
    Wait,
    /// Write the frame as PNG, at the window's size or the one given.
    Screenshot(PathBuf, Option<[u32; 2]>),
    /// Write the scene as JSON.
    Save(PathBuf),
    /// Read the scene from JSON.
    Load(PathBuf),
    /// Close the window.
    Quit,
}

/// Reads the script `path`; a line that is no command is named with its number.
pub fn read(path: &Path) -> Result<Vec<Command>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut commands = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let command = parse(line).map_err(|message| Error::File {
            path: path.to_path_buf(),
            message: format!("line {}: {message}: {line:?}", n + 1),
        })?;
        commands.push(command);
    }
    Ok(commands)
}

/// One command from its line.
fn parse(line: &str) -> std::result::Result<Command, String> {
    let (word, rest) = line.split_once(char::is_whitespace).unwrap_or((line, ""));
    let rest = rest.trim();
    let args: Vec<&str> = rest.split_whitespace().collect();
    let number = |s: &str| {
        s.parse::<f32>()
            .map_err(|_| format!("{s:?} is not a number"))
    };
    let count = |s: &str| {
        s.parse::<u32>()
            .map_err(|_| format!("{s:?} is not a count"))
    };
    match (word, args.as_slice()) {
        ("orbit", [degrees]) => Ok(Command::Orbit {
            degrees: number(degrees)?,
            frames: 1,
        }),
        ("orbit", [degrees, frames]) => Ok(Command::Orbit {
            degrees: number(degrees)?,
            frames: count(frames)?.max(1),
        }),
        ("set", [path, ..]) => {
            let json = rest[path.len()..].trim();
            let value = serde_json::from_str(json)
                .map_err(|e| format!("the value of {path} is not JSON ({e})"))?;
            Ok(Command::Set {
                path: (*path).to_string(),
                value,
            })
        }
        ("frames", [n]) => Ok(Command::Frames(count(n)?)),
        ("pick", [x, y]) => Ok(Command::Pick([number(x)?, number(y)?])),
        ("wait", []) => Ok(Command::Wait),
        ("screenshot", [file]) => Ok(Command::Screenshot(PathBuf::from(file), None)),
        ("screenshot", [file, size]) => {
            let (w, h) = size
                .split_once('x')
                .ok_or_else(|| format!("{size:?} is not WIDTHxHEIGHT"))?;
            Ok(Command::Screenshot(
                PathBuf::from(file),
                Some([count(w)?.max(1), count(h)?.max(1)]),
            ))
        }
        ("save", [file]) => Ok(Command::Save(PathBuf::from(file))),
        ("load", [file]) => Ok(Command::Load(PathBuf::from(file))),
        ("quit", []) => Ok(Command::Quit),
        _ => Err(
            "not a command (orbit, set, frames, pick, wait, screenshot, save, load, quit)".into(),
        ),
    }
}

/// `scene` with the field at `path` (dot-separated, as in the JSON scene) set to
/// `value`, checked; the field is named when the result is no scene.
pub fn set_field(scene: &Scene, path: &str, value: Value) -> Result<Scene> {
    let mut json = serde_json::to_value(scene).map_err(|e| Error::scene(e.to_string()))?;
    let mut slot = &mut json;
    for key in path.split('.') {
        if slot.is_null() {
            *slot = Value::Object(serde_json::Map::new());
        }
        let Value::Object(map) = slot else {
            return Err(Error::scene(format!(
                "scene field {path}: {key} is inside no object"
            )));
        };
        slot = map.entry(key.to_string()).or_insert(Value::Null);
    }
    *slot = value;
    let scene: Scene = serde_json::from_value(json)
        .map_err(|e| Error::scene(format!("scene field {path}: {e}")))?;
    scene.check()?;
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_parse_and_bad_lines_are_refused_with_the_reason() {
        assert_eq!(
            parse("orbit 90 30"),
            Ok(Command::Orbit {
                degrees: 90.0,
                frames: 30
            })
        );
        assert_eq!(
            parse(r#"set colour.property "PERMX""#),
            Ok(Command::Set {
                path: "colour.property".into(),
                value: Value::String("PERMX".into())
            })
        );
        assert_eq!(
            parse("screenshot a.png 640x480"),
            Ok(Command::Screenshot("a.png".into(), Some([640, 480])))
        );
        assert!(parse("orbit ninety").is_err_and(|e| e.contains("ninety")));
        assert!(parse("jump").is_err_and(|e| e.contains("not a command")));
        assert!(parse("set layers [1,").is_err_and(|e| e.contains("not JSON")));
    }

    #[test]
    fn fields_are_set_by_path_and_a_wrong_field_is_named() {
        let scene = Scene::of_model(crate::sample_model());
        let set = set_field(&scene, "layers", serde_json::json!([1, 3])).expect("layers");
        assert_eq!(set.layers, Some([1, 3]));
        let set =
            set_field(&set, "isolines", serde_json::json!({"property": "PORO"})).expect("isolines");
        assert_eq!(set.isolines.and_then(|i| i.property), Some("PORO".into()));
        let wrong = set_field(&scene, "wire.thicknes", serde_json::json!(2));
        assert!(wrong.is_err_and(|e| e.to_string().contains("thicknes")));
    }
}
