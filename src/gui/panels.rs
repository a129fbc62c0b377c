//! The right-hand panels: time, layers, and one section of sliders per
//! effect. The sliders are built from the preset itself and the
//! [`PARAMS`](crate::preset::PARAMS) table (range, meaning, paper symbol), so
//! a parameter added to the preset shows up here without GUI code: numbers
//! as sliders, switches as check boxes, and the rest through [`fields`]
//! (colours, choices, points, TOML text).

use eframe::egui;

use egui::{CollapsingHeader, Response, RichText, Sense, Shape, Slider, Stroke, Ui, vec2};

use crate::preset::{self, ParamSpec, Preset};

use super::command::{Command, PromptKind};
use super::controller::Controller;
use super::fields;
use super::state::LayerSetting;

/// The side panel: a welcome without a document; else time, layers and
/// parameters.
pub fn side(ui: &mut Ui, ctl: &Controller, out: &mut Vec<Command>) {
    let Some(l) = ctl.loaded() else {
        ui.add_space(8.0);
        ui.heading("grime");
        ui.label("Ages photos of buildings: rain streaks, moss and dust as layers.");
        ui.add_space(8.0);
        if ui.button("Try the sample facade").clicked() {
            out.push(Command::OpenDemo("facade".into()));
        }
        ui.add_space(4.0);
        ui.label("Or open a photo (File > Open image, Ctrl+O), or drop one onto the window.");
        return;
    };
    let preset = &l.doc.preset;
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            ui.add_space(4.0);
            ui.heading("Time");
            super::ages::panel(ui, ctl, out);
            time(ui, preset, out);
            ui.separator();
            ui.heading("Layers");
            let rows: Vec<LayerRow> = ctl.preview().current().map_or_else(Vec::new, |p| {
                p.stack
                    .layers
                    .iter()
                    .map(|layer| LayerRow {
                        name: layer.name.clone(),
                        opacity: layer.opacity,
                        visible: layer.visible,
                        setting: l.doc.layers.get(&layer.name).copied().unwrap_or_default(),
                    })
                    .collect()
            });
            layers(ui, &rows, out);
            ui.separator();
            ui.horizontal(|ui| {
                ui.heading("Parameters");
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    preset_buttons(ui, out)
                });
            });
            seed(ui, preset, out);
            super::say::panel(ui, preset, out);
            parameters(ui, preset, out);
        });
}

/// Save, load and built-in presets.
fn preset_buttons(ui: &mut Ui, out: &mut Vec<Command>) {
    if ui
        .button("Save…")
        .on_hover_text("Save the preset as commented TOML (same as the CLI's --preset)")
        .clicked()
    {
        out.push(Command::Prompt(PromptKind::SavePreset));
    }
    if ui
        .button("Load…")
        .on_hover_text("Load a preset TOML")
        .clicked()
    {
        out.push(Command::Prompt(PromptKind::LoadPreset));
    }
    egui::ComboBox::from_id_salt("builtin")
        .selected_text("Preset")
        .show_ui(ui, |ui| {
            for (name, about) in preset::BUILTIN {
                if ui
                    .selectable_label(false, *name)
                    .on_hover_text(*about)
                    .clicked()
                {
                    out.push(Command::BuiltinPreset(name.to_string()));
                }
            }
        })
        .response
        .on_hover_text("Built-in presets");
}

/// The time sliders: preset path and label. Paths missing from the preset
/// (an effect not built in) are skipped.
pub const TIME: &[(&str, &str)] = &[
    ("rain.layers", "Rainfalls"),
    ("moss.years", "Moss years"),
    ("dust.days", "Dust days"),
];

/// Section order and titles; other sections follow in preset order.
const SECTIONS: &[(&str, &str)] = &[
    ("rain", "Rain"),
    ("stain", "Stain"),
    ("moss", "Moss"),
    ("dust", "Dust"),
    ("sim", "Simulation"),
];

fn title(section: &str) -> String {
    SECTIONS.iter().find(|(s, _)| *s == section).map_or_else(
        || {
            let mut c = section.chars();
            c.next().map_or_else(String::new, |f| {
                f.to_uppercase().collect::<String>() + c.as_str()
            })
        },
        |(_, t)| t.to_string(),
    )
}

fn lookup<'a>(v: &'a toml::Value, path: &str) -> Option<&'a toml::Value> {
    path.split('.').try_fold(v, |v, k| v.get(k))
}

fn is_number(v: &toml::Value) -> bool {
    number(v).is_some()
}

fn number(v: &toml::Value) -> Option<(f64, bool)> {
    match v {
        toml::Value::Integer(i) => Some((*i as f64, true)),
        toml::Value::Float(f) => Some((*f, false)),
        _ => None,
    }
}

fn fmt_value(x: f64, integer: bool) -> String {
    if integer {
        format!("{}", x.round() as i64)
    } else {
        // Shortest text that reads back as the same f32.
        format!("{}", x as f32)
    }
}

fn tooltip(spec: &ParamSpec, default: Option<f64>) -> String {
    let mut t = spec.doc.to_string();
    if !spec.symbol.is_empty() {
        t.push_str(&format!("\nPaper symbol: {}", spec.symbol));
    }
    t.push_str(&format!(
        "\nPreset field: {}\nRange {} ..= {}",
        spec.path, spec.min, spec.max
    ));
    if let Some(d) = default {
        t.push_str(&format!(", default {d}"));
    }
    t
}

/// A numeric preset field's current state.
struct Num {
    value: f64,
    integer: bool,
    default: Option<f64>,
    /// Slider range, if narrower than the allowed one.
    range: Option<(f64, f64)>,
}

/// One slider for a numeric preset field, with tooltip and reset button.
fn param_slider(ui: &mut Ui, label: &str, spec: &ParamSpec, num: Num, out: &mut Vec<Command>) {
    let Num {
        value,
        integer,
        default,
        range,
    } = num;
    let (lo, hi) = range.unwrap_or((spec.min, spec.max));
    let typical = default.unwrap_or(value).abs().max(1e-3);
    let log = hi >= 50.0 * typical && hi > 0.0;
    let mut x = value;
    ui.horizontal(|ui| {
        let mut slider = Slider::new(&mut x, lo..=hi).text(label).logarithmic(log);
        if integer {
            slider = slider.integer();
        }
        let r = ui.add(slider).on_hover_text(tooltip(spec, default));
        if r.changed() && x != value {
            let merge = r.dragged() && !r.drag_started();
            out.push(Command::SetParam {
                path: spec.path.to_string(),
                value: fmt_value(x, integer),
                merge,
            });
        }
        if let Some(d) = default {
            let reset = reset_button(ui, d != value, &format!("Reset {}", spec.path))
                .on_hover_text(format!("Reset {} to its default, {d}", spec.path));
            if reset.clicked() {
                out.push(Command::SetParam {
                    path: spec.path.to_string(),
                    value: fmt_value(d, integer),
                    merge: false,
                });
            }
        }
    });
}

/// The time sliders (number of rainfalls, moss years, dust days).
pub fn time(ui: &mut Ui, preset: &Preset, out: &mut Vec<Command>) {
    let (Ok(value), Ok(defaults)) = (
        toml::Value::try_from(preset),
        toml::Value::try_from(Preset::default()),
    ) else {
        return;
    };
    for (path, label) in TIME {
        let (Some(v), Some(spec)) = (lookup(&value, path).and_then(number), preset::param(path))
        else {
            continue;
        };
        let default = lookup(&defaults, path).and_then(number).map(|d| d.0);
        // A usable scrubbing range: up to 4x the default (or the current value).
        let hi = spec
            .max
            .min((default.unwrap_or(v.0).max(v.0) * 4.0).max(10.0));
        let num = Num {
            value: v.0,
            integer: v.1,
            default,
            range: Some((spec.min, hi)),
        };
        param_slider(ui, label, spec, num, out);
    }
}

/// Every preset parameter, one collapsible section per effect.
pub fn parameters(ui: &mut Ui, preset: &Preset, out: &mut Vec<Command>) {
    let (Ok(value), Ok(defaults)) = (
        toml::Value::try_from(preset),
        toml::Value::try_from(Preset::default()),
    ) else {
        return;
    };
    let Some(root) = value.as_table() else { return };
    let mut sections: Vec<&str> = SECTIONS
        .iter()
        .map(|(s, _)| *s)
        .filter(|s| root.get(*s).is_some_and(toml::Value::is_table))
        .collect();
    for (k, v) in root {
        if v.is_table() && !sections.contains(&k.as_str()) {
            sections.insert(sections.len().saturating_sub(1), k);
        }
    }
    for section in sections {
        let Some(table) = root.get(section).and_then(toml::Value::as_table) else {
            continue;
        };
        CollapsingHeader::new(RichText::new(title(section)).strong())
            .id_salt(section)
            .default_open(matches!(section, "rain" | "stain" | "moss" | "dust"))
            .show(ui, |ui| {
                // The PARAMS table's order (meaningful), then the rest.
                let prefix = format!("{section}.");
                let mut keys: Vec<&str> = preset::PARAMS
                    .iter()
                    .filter_map(|s| s.path.strip_prefix(&prefix))
                    .filter(|k| table.contains_key(*k))
                    .collect();
                for k in table.keys() {
                    if !keys.contains(&k.as_str()) {
                        keys.push(k);
                    }
                }
                for key in keys {
                    let Some(v) = table.get(key) else { continue };
                    let path = format!("{section}.{key}");
                    let default = lookup(&defaults, &path);
                    match v {
                        toml::Value::Integer(_) | toml::Value::Float(_) => {
                            if let (Some(spec), Some((x, integer))) =
                                (preset::param(&path), number(v))
                            {
                                let default = default.and_then(number).map(|d| d.0);
                                param_slider(
                                    ui,
                                    key,
                                    spec,
                                    Num {
                                        value: x,
                                        integer,
                                        default,
                                        range: None,
                                    },
                                    out,
                                );
                            }
                        }
                        toml::Value::Boolean(b) => {
                            let mut on = *b;
                            let doc =
                                preset::param(&path).map_or(path.clone(), |s| s.doc.to_string());
                            if ui.checkbox(&mut on, key).on_hover_text(doc).changed() {
                                out.push(Command::SetParam {
                                    path,
                                    value: on.to_string(),
                                    merge: false,
                                });
                            }
                        }
                        toml::Value::Array(a) if a.len() == 3 && key.contains("color") => {
                            fields::colour(ui, key, &path, a, default, out);
                        }
                        toml::Value::String(s) => match preset::param(&path) {
                            Some(spec) if !spec.choices.is_empty() => {
                                fields::choice(ui, key, spec, s, default, out);
                            }
                            _ => fields::text(ui, key, &path, v, default, out),
                        },
                        toml::Value::Array(a)
                            if !a.is_empty() && a.len() <= 4 && a.iter().all(is_number) =>
                        {
                            fields::numbers(ui, key, &path, a, default, out);
                        }
                        other => fields::text(ui, key, &path, other, default, out),
                    }
                }
            });
    }
}

/// The seed, with a dice button for a new random one.
pub fn seed(ui: &mut Ui, preset: &Preset, out: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        let label = ui.label("Seed");
        let mut seed = preset.seed;
        let tip = preset::param("seed").map_or("", |s| s.doc);
        let r = ui
            .add(egui::DragValue::new(&mut seed).range(0..=i64::MAX as u64))
            .labelled_by(label.id)
            .on_hover_text(tip);
        if r.changed() {
            out.push(Command::SetParam {
                path: "seed".into(),
                value: seed.to_string(),
                merge: r.dragged(),
            });
        }
        if ui
            .button("Random")
            .on_hover_text("A new random seed: another variation of the same weathering")
            .clicked()
        {
            let new = rand::random::<u32>() as u64;
            out.push(Command::SetParam {
                path: "seed".into(),
                value: new.to_string(),
                merge: false,
            });
        }
    });
}

/// One row of the layer panel.
#[derive(Debug, Clone)]
pub struct LayerRow {
    /// Layer name.
    pub name: String,
    /// Current opacity.
    pub opacity: f32,
    /// Currently shown.
    pub visible: bool,
    /// The user's setting for it.
    pub setting: LayerSetting,
}

/// The layer list: visibility and opacity per layer, top layer first.
pub fn layers(ui: &mut Ui, rows: &[LayerRow], out: &mut Vec<Command>) {
    if rows.is_empty() {
        ui.weak("No layers yet.");
        return;
    }
    egui::ScrollArea::vertical()
        .id_salt("layers")
        .max_height(180.0)
        .show(ui, |ui| {
            egui::Grid::new("layer grid")
                .num_columns(2)
                .striped(true)
                .show(ui, |ui| {
                    for row in rows.iter().rev() {
                        let mut visible = row.setting.visible;
                        let vis = ui
                            .horizontal(|ui| {
                                let r = ui
                                    .checkbox(&mut visible, row.name.as_str())
                                    .on_hover_text("Show this layer (and export it)");
                                if visible && !row.visible {
                                    ui.weak("later").on_hover_text(
                                        "Beyond the time slider: shown when you move it forward",
                                    );
                                }
                                r
                            })
                            .inner;
                        let mut opacity = row.opacity;
                        let op = ui.add(
                            Slider::new(&mut opacity, 0.0..=1.0)
                                .text("opacity")
                                .fixed_decimals(2),
                        );
                        if vis.changed() {
                            out.push(Command::SetLayer {
                                name: row.name.clone(),
                                setting: LayerSetting {
                                    visible,
                                    ..row.setting
                                },
                            });
                        }
                        if op.changed() {
                            let setting = LayerSetting {
                                opacity: Some(opacity),
                                ..row.setting
                            };
                            out.push(Command::SetLayer {
                                name: row.name.clone(),
                                setting,
                            });
                        }
                        ui.end_row();
                    }
                });
        });
    if ui
        .small_button("Reset layers")
        .on_hover_text("Show every layer at the preset's opacity")
        .clicked()
    {
        out.push(Command::ResetLayers);
    }
}

/// A small "reset" button: a circular arrow, named `name` for screen
/// readers and tests.
pub(super) fn reset_button(ui: &mut Ui, enabled: bool, name: &str) -> Response {
    let sense = if enabled {
        Sense::click()
    } else {
        Sense::hover()
    };
    let (rect, resp) = ui.allocate_exact_size(vec2(18.0, 18.0), sense);
    let name = name.to_string();
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, enabled, &name));
    if ui.is_rect_visible(rect) {
        let painter = ui.painter();
        let color = if !enabled {
            ui.visuals().weak_text_color().gamma_multiply(0.5)
        } else if resp.hovered() {
            painter.rect_filled(rect, 3.0, ui.visuals().widgets.hovered.weak_bg_fill);
            ui.visuals().strong_text_color()
        } else {
            ui.visuals().text_color()
        };
        let c = rect.center();
        let r = 5.0;
        let (a0, a1) = (-2.2f32, 2.4f32);
        let arc: Vec<_> = (0..=16)
            .map(|i| {
                let a = a0 + (a1 - a0) * i as f32 / 16.0;
                c + vec2(a.cos(), a.sin()) * r
            })
            .collect();
        painter.add(Shape::line(arc, Stroke::new(1.4, color)));
        // Arrow head at the start of the arc, pointing back along it.
        let tip = c + vec2(a0.cos(), a0.sin()) * r;
        let tangent = vec2(a0.sin(), -a0.cos());
        let normal = vec2(a0.cos(), a0.sin());
        painter.add(Shape::convex_polygon(
            vec![tip + tangent * 3.5, tip + normal * 2.8, tip - normal * 2.8],
            color,
            Stroke::NONE,
        ));
    }
    resp
}
