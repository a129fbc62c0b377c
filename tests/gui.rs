//! The GUI driven like a user would: by widget labels, with egui_kittest
//! (no GPU, no display). Each test waits for the preview worker for real.
#![cfg(feature = "gui")]

use std::path::Path;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use grime::gui::egui::{
    self, ColorImage, Event, Key, Modifiers, PointerButton, Pos2, accesskit::Role,
};
use grime::gui::{AppOptions, GrimeApp};
use grime::preset::Preset;

/// A lighter preset so each preview takes a fraction of a second.
fn quick_preset() -> Preset {
    let mut p = Preset::default();
    p.rain.layers = 3;
    p.rain.droplets = 300;
    p
}

fn harness(options: AppOptions) -> Harness<'static, GrimeApp> {
    Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .with_max_steps(20)
        .build_ui_state(
            |ui, app: &mut GrimeApp| app.show(ui),
            GrimeApp::new(options),
        )
}

/// Steps frames until the preview and export workers are idle.
fn settle(h: &mut Harness<'static, GrimeApp>) {
    let start = Instant::now();
    loop {
        h.step();
        if !h.state().is_busy() {
            h.step();
            if !h.state().is_busy() {
                return;
            }
        }
        assert!(
            start.elapsed() < Duration::from_secs(600),
            "the workers never finished"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn canvas_point(h: &Harness<'static, GrimeApp>, fx: f32, fy: f32) -> Pos2 {
    let r = h.get_by_label("Canvas").rect();
    r.min + egui::vec2(r.width() * fx, r.height() * fy)
}

fn press(h: &Harness<'static, GrimeApp>, pos: Pos2, pressed: bool) {
    h.event(Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    });
}

/// Drags between two points given as fractions of the canvas.
fn drag(h: &mut Harness<'static, GrimeApp>, a: (f32, f32), b: (f32, f32)) {
    let (a, b) = (canvas_point(h, a.0, a.1), canvas_point(h, b.0, b.1));
    h.hover_at(a);
    press(h, a, true);
    for k in 1..=8 {
        h.hover_at(a + (b - a) * (k as f32 / 8.0));
    }
    press(h, b, false);
    h.step();
}

/// Clicks at a point given as fractions of the canvas.
fn click_at(h: &mut Harness<'static, GrimeApp>, fx: f32, fy: f32) {
    let p = canvas_point(h, fx, fy);
    h.hover_at(p);
    press(h, p, true);
    press(h, p, false);
    h.step();
}

/// Clicks a widget by its label and lets the UI react.
fn click(h: &mut Harness<'static, GrimeApp>, label: &str) {
    h.get_by_label(label).click();
    h.run_steps(3);
}

/// Pixels where two images differ.
fn diff(a: &ColorImage, b: &ColorImage) -> Vec<usize> {
    assert_eq!(a.size, b.size);
    a.pixels
        .iter()
        .zip(&b.pixels)
        .enumerate()
        .filter(|(_, (p, q))| p != q)
        .map(|(i, _)| i)
        .collect()
}

fn open_facade(h: &mut Harness<'static, GrimeApp>) {
    click(h, "File");
    click(h, "Open sample: facade");
    settle(h);
}

#[test]
fn paint_region_add_line_tune_undo_and_export() {
    let mut h = harness(AppOptions {
        preset: quick_preset(),
        ..AppOptions::default()
    });
    open_facade(&mut h);
    h.check_accessibility(); // every input widget has a name
    let photo = h.state().proxy_image().expect("the sample is open");
    let first = h.state().preview_image().expect("a first preview").clone();
    assert!(!diff(&first, &photo).is_empty(), "the sample ages");

    // Region: clear it, then drag a rectangle over the middle of the facade.
    click(&mut h, "Clear");
    settle(&mut h);
    assert!(
        h.state()
            .message()
            .is_some_and(|(m, err)| err && m.contains("empty")),
        "{:?}",
        h.state().message()
    );
    click(&mut h, "Rectangle");
    drag(&mut h, (0.30, 0.25), (0.70, 0.75));
    settle(&mut h);
    let mask = h.state().proxy_mask().unwrap().clone();
    let painted = mask.iter().filter(|&&m| m > 0).count();
    assert!(
        painted > 50_000 && painted < 300_000,
        "painted {painted} px"
    );
    let inside = |i: usize| mask.as_raw()[i] > 0;

    // A source line across the top of the region.
    let lines_before = h.state().document().unwrap().lines.len();
    click(&mut h, "Line");
    click_at(&mut h, 0.35, 0.35);
    click_at(&mut h, 0.65, 0.35);
    h.key_press(Key::Enter);
    h.step();
    settle(&mut h);
    assert_eq!(h.state().document().unwrap().lines.len(), lines_before + 1);
    let before = h
        .state()
        .preview_image()
        .expect("preview of the region")
        .clone();
    let changed = diff(&before, &photo);
    assert!(!changed.is_empty(), "the region ages");
    assert!(
        changed.iter().all(|&i| inside(i)),
        "only the region changes"
    );

    // A slider: the wall's absorption k_a.
    h.get_by_role_and_label(Role::Slider, "k_a")
        .set_value_accesskit(0.95);
    h.step();
    assert_eq!(h.state().document().unwrap().preset.rain.k_a, 0.95);
    settle(&mut h);
    let after = h.state().preview_image().unwrap().clone();
    let changed = diff(&after, &before);
    assert!(!changed.is_empty(), "k_a changes the streaks");
    assert!(
        changed.iter().all(|&i| inside(i)),
        "the preview changed only inside the region"
    );
    assert!(diff(&after, &photo).iter().all(|&i| inside(i)));

    // Undo brings the parameter and the picture back.
    click(&mut h, "Undo");
    assert_eq!(
        h.state().document().unwrap().preset.rain.k_a,
        Preset::default().rain.k_a
    );
    settle(&mut h);
    assert!(
        diff(h.state().preview_image().unwrap(), &before).is_empty(),
        "undo restores the preview"
    );
    // Redo with the keyboard, then undo again.
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.step();
    assert_eq!(h.state().document().unwrap().preset.rain.k_a, 0.95);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.step();
    settle(&mut h);

    // Export at full resolution and read it back.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("aged.png");
    click(&mut h, "Export…");
    h.get_by_label("Path")
        .set_text_value_accesskit(out.to_str().unwrap());
    h.step();
    click(&mut h, "Export now");
    settle(&mut h);
    assert!(
        matches!(h.state().last_export(), Some(Ok(_))),
        "{:?}",
        h.state().message()
    );
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (960, 720));
    // The sample is under 1 MP, so the preview ran at full size: same pixels.
    let preview = h.state().preview_image().unwrap();
    let same = img
        .pixels()
        .zip(&preview.pixels)
        .all(|(p, c)| p.0 == [c.r(), c.g(), c.b()]);
    assert!(same, "the export matches the preview");
}

#[test]
fn unreadable_images_and_failed_writes_show_messages() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.jpg");
    std::fs::write(&bad, b"not a jpeg at all").unwrap();
    let mut h = harness(AppOptions {
        preset: quick_preset(),
        ..AppOptions::default()
    });
    h.step();
    click(&mut h, "File");
    click(&mut h, "Open image…");
    h.get_by_label("Path")
        .set_text_value_accesskit(bad.to_str().unwrap());
    h.step();
    click(&mut h, "Open");
    h.step();
    let (msg, err) = h.state().message().expect("a message");
    assert!(err && msg.contains("broken.jpg"), "{msg}");
    assert!(h.state().document().is_none());

    open_facade(&mut h);
    for target in [
        Path::new("/nonexistent-grime-dir/aged.png"),
        Path::new("aged.bmpx"),
    ] {
        click(&mut h, "Export…");
        h.get_by_label("Path")
            .set_text_value_accesskit(target.to_str().unwrap());
        h.step();
        click(&mut h, "Export now");
        settle(&mut h);
        let (msg, err) = h.state().message().expect("a message");
        assert!(
            err && (msg.contains("does not exist") || msg.contains("unknown image extension")),
            "{msg}"
        );
    }
}

#[test]
fn time_slider_and_layers_recomposite_without_simulating() {
    let mut p = quick_preset();
    p.rain.layers = 4;
    for effect in ["moss", "dust"] {
        let _ = p.set(&format!("{effect}.enabled=false"));
    }
    let mut h = harness(AppOptions {
        preset: p,
        ..AppOptions::default()
    });
    open_facade(&mut h);
    let four = h.state().preview_image().unwrap().clone();
    h.get_by_role_and_label(Role::Slider, "Rainfalls")
        .set_value_accesskit(2.0);
    h.step();
    // No simulation: the preview is already there in the same frame.
    assert!(!h.state().is_busy());
    let two = h.state().preview_image().unwrap().clone();
    assert!(!diff(&two, &four).is_empty());
    // Hiding a layer in the layer panel changes the composite too.
    click(&mut h, "rain 01");
    assert!(!h.state().is_busy());
    assert!(!diff(h.state().preview_image().unwrap(), &two).is_empty());
    assert!(!h.state().document().unwrap().layers["rain 01"].visible);
}

#[test]
fn lasso_wand_detect_ledges_and_quad() {
    let mut h = harness(AppOptions {
        preset: quick_preset(),
        ..AppOptions::default()
    });
    open_facade(&mut h);
    let n0 = h.state().document().unwrap().lines.len();
    click(&mut h, "Detect ledges");
    settle(&mut h);
    // The sample's ledges are already lines: detection adds few or none.
    assert!(h.state().document().unwrap().lines.len() <= n0 + 3);

    click(&mut h, "Clear");
    click(&mut h, "Lasso");
    for (fx, fy) in [(0.2, 0.3), (0.5, 0.3), (0.5, 0.6)] {
        click_at(&mut h, fx, fy);
    }
    h.key_press(Key::Enter);
    h.step();
    let lasso = h
        .state()
        .document()
        .unwrap()
        .mask
        .iter()
        .filter(|&&m| m > 0)
        .count();
    assert!(lasso > 10_000, "lasso filled {lasso}");

    click(&mut h, "Wand");
    click_at(&mut h, 0.5, 0.03); // the sky
    let wand = h
        .state()
        .document()
        .unwrap()
        .mask
        .iter()
        .filter(|&&m| m > 0)
        .count();
    assert!(
        wand > lasso + 10_000,
        "wand added the sky: {lasso} -> {wand}"
    );

    click(&mut h, "Quad");
    drag(&mut h, (0.1, 0.2), (0.9, 0.9));
    assert!(h.state().document().unwrap().quad.is_some());
    settle(&mut h);
    assert!(
        h.state().preview_image().is_some(),
        "{:?}",
        h.state().message()
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.step();
    assert!(
        h.state().document().unwrap().quad.is_none(),
        "undo removes the quad"
    );
    settle(&mut h);
}

#[test]
fn presets_and_projects_round_trip_through_the_ui() {
    let dir = tempfile::tempdir().unwrap();
    let preset_path = dir.path().join("mine.toml");
    let project = dir.path().join("facade.grime.json");
    let mut h = harness(AppOptions {
        preset: quick_preset(),
        ..AppOptions::default()
    });
    open_facade(&mut h);
    h.get_by_role_and_label(Role::Slider, "k_s")
        .set_value_accesskit(0.4);
    h.step();
    click(&mut h, "Save…");
    h.get_by_label("Path")
        .set_text_value_accesskit(preset_path.to_str().unwrap());
    h.step();
    click(&mut h, "Save");
    let saved = Preset::from_toml(&std::fs::read_to_string(&preset_path).unwrap()).unwrap();
    assert_eq!(saved.rain.k_s, 0.4);
    assert!(
        !saved.rain.source_lines.is_empty(),
        "the lines go with the preset, as for the CLI"
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.step();
    h.get_by_label("Path")
        .set_text_value_accesskit(project.to_str().unwrap());
    h.step();
    click(&mut h, "Save");
    assert!(
        project.exists() && dir.path().join("facade.mask.png").exists(),
        "{:?}",
        h.state().message()
    );
    settle(&mut h);

    let mut h2 = harness(AppOptions {
        image: Some(project),
        ..AppOptions::default()
    });
    h2.step();
    settle(&mut h2);
    let (a, b) = (
        h.state().document().unwrap(),
        h2.state().document().unwrap(),
    );
    assert_eq!(a, b);
    assert!(
        diff(
            h.state().preview_image().unwrap(),
            h2.state().preview_image().unwrap()
        )
        .is_empty()
    );
}

#[test]
fn brush_and_eraser_paint_the_region() {
    let mut h = harness(AppOptions {
        preset: quick_preset(),
        ..AppOptions::default()
    });
    open_facade(&mut h);
    click(&mut h, "Clear");
    click(&mut h, "Brush");
    drag(&mut h, (0.2, 0.5), (0.8, 0.5));
    let painted = h
        .state()
        .document()
        .unwrap()
        .mask
        .iter()
        .filter(|&&m| m > 0)
        .count();
    assert!(painted > 5_000, "{painted}");
    click(&mut h, "Eraser");
    drag(&mut h, (0.2, 0.5), (0.8, 0.5));
    let left = h
        .state()
        .document()
        .unwrap()
        .mask
        .iter()
        .filter(|&&m| m >= 128)
        .count();
    assert!(left < painted / 4, "{painted} -> {left}");
    settle(&mut h);
    // One undo step per stroke.
    click(&mut h, "Undo");
    assert_eq!(
        h.state()
            .document()
            .unwrap()
            .mask
            .iter()
            .filter(|&&m| m > 0)
            .count(),
        painted
    );
}
