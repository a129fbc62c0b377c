//! The generic parameter panel's widgets for the fields that are not one
//! number or a switch: a colour, one word of a list (the
//! [`ParamSpec::choices`] column of the PARAMS table), a few numbers (a
//! point), and anything else as its TOML text. Each reads the preset's
//! value and emits [`Command::SetParam`]s; none knows an effect.

use eframe::egui;

use egui::{DragValue, Ui};

use crate::preset::{self, ParamSpec};

use super::command::Command;
use super::panels::reset_button;

/// The tooltip of a field: its doc and its path.
fn doc(path: &str) -> String {
    preset::param(path).map_or(path.to_string(), |s| {
        format!("{}\nPreset field: {path}", s.doc)
    })
}

/// A reset button that sets `default` (a TOML value) when it differs.
fn reset(
    ui: &mut Ui,
    path: &str,
    v: &toml::Value,
    default: Option<&toml::Value>,
) -> Option<Command> {
    let d = default?;
    reset_button(ui, d != v, &format!("Reset {path}"))
        .on_hover_text(format!("Reset {path} to its default, {d}"))
        .clicked()
        .then(|| Command::SetParam {
            path: path.to_string(),
            value: d.to_string(),
            merge: false,
        })
}

/// A colour button for an `[r, g, b]` field.
pub fn colour(
    ui: &mut Ui,
    key: &str,
    path: &str,
    a: &[toml::Value],
    default: Option<&toml::Value>,
    out: &mut Vec<Command>,
) {
    let mut rgb = [0u8; 3];
    for (c, x) in rgb.iter_mut().zip(a) {
        *c = x.as_integer().unwrap_or(0).clamp(0, 255) as u8;
    }
    ui.horizontal(|ui| {
        let r = ui.color_edit_button_srgb(&mut rgb).on_hover_text(doc(path));
        ui.label(key);
        if r.changed() {
            out.push(Command::SetParam {
                path: path.to_string(),
                value: format!("[{}, {}, {}]", rgb[0], rgb[1], rgb[2]),
                merge: true,
            });
        }
        let v = toml::Value::Array(a.to_vec());
        out.extend(reset(ui, path, &v, default));
    });
}

/// A choice box for a string field that takes one of `spec.choices`.
pub fn choice(
    ui: &mut Ui,
    key: &str,
    spec: &ParamSpec,
    current: &str,
    default: Option<&toml::Value>,
    out: &mut Vec<Command>,
) {
    let path = spec.path;
    ui.horizontal(|ui| {
        let mut picked = current.to_string();
        egui::ComboBox::from_label(key)
            .selected_text(current)
            .show_ui(ui, |ui| {
                for c in spec.choices {
                    ui.selectable_value(&mut picked, c.to_string(), *c);
                }
            })
            .response
            .on_hover_text(doc(path));
        if picked != current {
            out.push(Command::SetParam {
                path: path.to_string(),
                value: toml::Value::String(picked).to_string(),
                merge: false,
            });
        }
        let v = toml::Value::String(current.to_string());
        out.extend(reset(ui, path, &v, default));
    });
}

/// One drag box per number of a short numeric array (a point `[x, y]`).
pub fn numbers(
    ui: &mut Ui,
    key: &str,
    path: &str,
    a: &[toml::Value],
    default: Option<&toml::Value>,
    out: &mut Vec<Command>,
) {
    let (lo, hi) = preset::param(path).map_or((f64::MIN, f64::MAX), |s| (s.min, s.max));
    let mut xs: Vec<f64> = a
        .iter()
        .map(|x| {
            x.as_float()
                .or(x.as_integer().map(|i| i as f64))
                .unwrap_or(0.0)
        })
        .collect();
    ui.horizontal(|ui| {
        let label = ui.label(key);
        let mut changed = false;
        let mut dragged = false;
        for x in &mut xs {
            let r = ui
                .add(DragValue::new(x).range(lo..=hi).speed(1.0))
                .labelled_by(label.id)
                .on_hover_text(doc(path));
            changed |= r.changed();
            dragged |= r.dragged();
        }
        if changed {
            let v: Vec<String> = xs.iter().map(|x| format!("{}", *x as f32)).collect();
            out.push(Command::SetParam {
                path: path.to_string(),
                value: format!("[{}]", v.join(", ")),
                merge: dragged,
            });
        }
        out.extend(reset(ui, path, &toml::Value::Array(a.to_vec()), default));
    });
}

/// Any other value as its TOML text, set when the box loses focus (Enter
/// or a click elsewhere); the preset checks it like `--set`.
pub fn text(
    ui: &mut Ui,
    key: &str,
    path: &str,
    v: &toml::Value,
    default: Option<&toml::Value>,
    out: &mut Vec<Command>,
) {
    let id = ui.make_persistent_id(("toml text", path));
    let buffer = id.with("buffer");
    let current = v.to_string();
    ui.horizontal(|ui| {
        let label = ui.label(key);
        let editing = ui.memory(|m| m.has_focus(id));
        let mut text = if editing {
            ui.data_mut(|d| d.get_temp::<String>(buffer))
                .unwrap_or_else(|| current.clone())
        } else {
            current.clone()
        };
        let r = ui
            .add(
                egui::TextEdit::singleline(&mut text)
                    .id(id)
                    .desired_width((ui.available_width() - 30.0).max(60.0)),
            )
            .labelled_by(label.id)
            .on_hover_text(format!("{}\nTOML; set when you press Enter", doc(path)));
        // An edit without focus (a screen reader's) is set at once.
        if r.lost_focus() || (r.changed() && !r.has_focus()) {
            ui.data_mut(|d| d.remove::<String>(buffer));
            if text != current {
                out.push(Command::SetParam {
                    path: path.to_string(),
                    value: text,
                    merge: false,
                });
            }
        } else if r.has_focus() {
            ui.data_mut(|d| d.insert_temp(buffer, text));
        }
        out.extend(reset(ui, path, v, default));
    });
}
