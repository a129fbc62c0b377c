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

/// A harness with `preset` and the sample facade open and previewed.
fn facade_with(preset: Preset) -> Harness<'static, GrimeApp> {
    let mut h = harness(AppOptions {
        preset,
        ..AppOptions::default()
    });
    open_facade(&mut h);
    h
}

/// Answers the path prompt that `button` opens with `path`, confirms it
/// with `confirm`, and waits for the workers (file I/O runs off the UI
/// thread).
fn prompt(h: &mut Harness<'static, GrimeApp>, button: &str, path: &Path, confirm: &str) {
    click(h, button);
    h.get_by_label("Path")
        .set_text_value_accesskit(path.to_str().unwrap());
    h.step();
    click(h, confirm);
    settle(h);
}

/// Mask pixels of the document at or above `at`.
fn mask_count(h: &Harness<'static, GrimeApp>, at: u8) -> usize {
    let doc = h.state().document().expect("a document");
    doc.mask.iter().filter(|&&m| m >= at).count()
}

/// The status bar message, which must be an error.
fn error_message(h: &Harness<'static, GrimeApp>) -> String {
    let (msg, err) = h.state().message().expect("a message");
    assert!(err, "not an error: {msg}");
    msg.to_string()
}

/// Moss and dust off: every layer is a rain layer.
fn rain_only(p: &mut Preset) {
    p.moss.enabled = false;
    p.dust.enabled = false;
}

#[test]
fn paint_region_add_line_tune_undo_and_export() {
    let mut h = facade_with(quick_preset());
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
    prompt(&mut h, "Export…", &out, "Export now");
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
    prompt(&mut h, "Open image…", &bad, "Open");
    let msg = error_message(&h);
    assert!(msg.contains("broken.jpg"), "{msg}");
    assert!(h.state().document().is_none());

    open_facade(&mut h);
    for target in [
        Path::new("/nonexistent-grime-dir/aged.png"),
        Path::new("aged.bmpx"),
    ] {
        prompt(&mut h, "Export…", target, "Export now");
        let msg = error_message(&h);
        assert!(
            msg.contains("does not exist") || msg.contains("unknown image extension"),
            "{msg}"
        );
    }
}

#[test]
fn time_slider_and_layers_recomposite_without_simulating() {
    let mut p = quick_preset();
    p.rain.layers = 4;
    // Without the washed runs, which sum every rainfall (fewer need a run).
    p.stain.washed_opacity = 0.0;
    rain_only(&mut p);
    let mut h = facade_with(p);
    let simulations = h.state().controller().preview().simulations();
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
    assert_eq!(
        h.state().controller().preview().simulations(),
        simulations,
        "the worker never started"
    );
}

#[test]
fn lasso_wand_detect_ledges_and_quad() {
    let mut h = facade_with(quick_preset());
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
    let lasso = mask_count(&h, 1);
    assert!(lasso > 10_000, "lasso filled {lasso}");

    click(&mut h, "Wand");
    click_at(&mut h, 0.5, 0.03); // the sky
    let wand = mask_count(&h, 1);
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
    let mut h = facade_with(quick_preset());
    h.get_by_role_and_label(Role::Slider, "k_s")
        .set_value_accesskit(0.4);
    h.step();
    prompt(&mut h, "Save…", &preset_path, "Save");
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
    settle(&mut h);
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
    let mut h = facade_with(quick_preset());
    click(&mut h, "Clear");
    click(&mut h, "Brush");
    drag(&mut h, (0.2, 0.5), (0.8, 0.5));
    let painted = mask_count(&h, 1);
    assert!(painted > 5_000, "{painted}");
    click(&mut h, "Eraser");
    drag(&mut h, (0.2, 0.5), (0.8, 0.5));
    let left = mask_count(&h, 128);
    assert!(left < painted / 4, "{painted} -> {left}");
    settle(&mut h);
    // One undo step per stroke.
    click(&mut h, "Undo");
    assert_eq!(mask_count(&h, 1), painted);
}

#[test]
fn the_stain_opacity_slider_restyles_without_the_simulation_worker() {
    let mut p = quick_preset();
    rain_only(&mut p);
    let mut h = facade_with(p);
    let before = h.state().preview_image().unwrap().clone();
    let simulations = h.state().controller().preview().simulations();
    // The layer panel's rows come first (the rainfalls and the washed
    // runs), then the Stain section's slider (the Moss section's "opacity"
    // is last).
    let layers = h.state().document().unwrap().preset.rain.layers as usize + 1;
    let sliders: Vec<_> = h
        .get_all_by_role_and_label(Role::Slider, "opacity")
        .collect();
    assert_eq!(sliders.len(), layers + 2);
    sliders[layers].set_value_accesskit(0.3);
    h.step();
    assert_eq!(h.state().document().unwrap().preset.stain.opacity, 0.3);
    assert!(!h.state().is_busy(), "re-composited in the same frame");
    settle(&mut h);
    assert_eq!(
        h.state().controller().preview().simulations(),
        simulations,
        "a restyle-only change never starts the simulation worker"
    );
    assert!(!diff(h.state().preview_image().unwrap(), &before).is_empty());
}

#[test]
fn a_dust_change_re_runs_only_the_dust() {
    let mut h = facade_with(quick_preset());
    let stages = |h: &Harness<'static, GrimeApp>| -> Vec<String> {
        let preview = h.state().controller().preview().current().unwrap();
        preview.timings.iter().map(|t| t.stage.clone()).collect()
    };
    assert!(!stages(&h).iter().any(|s| s.ends_with("(kept)")));
    let days = h.state().document().unwrap().preset.dust.days;
    h.get_by_role_and_label(Role::Slider, "Dust days")
        .set_value_accesskit(f64::from(days + 30));
    h.step();
    assert_eq!(h.state().document().unwrap().preset.dust.days, days + 30);
    settle(&mut h);
    let s = stages(&h);
    for kept in ["rain (kept)", "moss (kept)"] {
        assert!(s.iter().any(|t| t == kept), "{kept} not in {s:?}");
    }
    assert!(s.iter().any(|t| t == "dust"), "{s:?}");
}

#[test]
fn export_refuses_to_overwrite_the_photo_or_the_project_mask() {
    let dir = tempfile::tempdir().unwrap();
    let photo = dir.path().join("wall.png");
    let d = grime::demo::facade(240, 180);
    grime::io::save_image(d.photo.image(), None, &photo).unwrap();
    let bytes = std::fs::read(&photo).unwrap();
    let mut h = harness(AppOptions {
        image: Some(photo.clone()),
        preset: quick_preset(),
        ..AppOptions::default()
    });
    settle(&mut h);
    assert!(h.state().document().is_some(), "{:?}", h.state().message());
    prompt(&mut h, "Export…", &photo, "Export now");
    let msg = error_message(&h);
    assert!(msg.contains("refusing to overwrite an input"), "{msg}");
    assert_eq!(std::fs::read(&photo).unwrap(), bytes, "the photo is intact");

    // A project's mask file is an input too.
    let project = dir.path().join("wall.grime.json");
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.step();
    h.get_by_label("Path")
        .set_text_value_accesskit(project.to_str().unwrap());
    h.step();
    click(&mut h, "Save");
    settle(&mut h);
    let mask = dir.path().join("wall.mask.png");
    let mut h = harness(AppOptions {
        image: Some(project),
        ..AppOptions::default()
    });
    settle(&mut h);
    prompt(&mut h, "Export…", &mask, "Export now");
    let msg = error_message(&h);
    assert!(msg.contains("refusing to overwrite an input"), "{msg}");
    // Another name is fine.
    prompt(
        &mut h,
        "Export…",
        &dir.path().join("aged.png"),
        "Export now",
    );
    assert!(matches!(h.state().last_export(), Some(Ok(_))));
}

#[test]
fn scrubbing_the_age_shows_cached_frames_without_the_simulation_worker() {
    let mut p = quick_preset();
    p.age.years = Some(4);
    let p = grime::clock::resolve(&p, grime::clock::Pins::none()).unwrap();
    let mut h = facade_with(p);
    let simulations = h.state().controller().preview().simulations();
    let now = h.state().preview_image().unwrap().clone();
    h.get_by_role_and_label(Role::Slider, "Age (years)")
        .set_value_accesskit(0.0);
    h.step();
    assert!(!h.state().is_busy(), "no simulation to wait for");
    let zero = h.state().preview_image().unwrap().clone();
    assert!(!diff(&zero, &now).is_empty(), "year 0 is not the aged wall");
    // Year 0 is the photo.
    let photo = {
        let l = h.state().controller().loaded().unwrap();
        grime::gui::render::to_color_image(l.proxy.photo.image())
    };
    assert!(diff(&zero, &photo).is_empty(), "year 0 shows the photo");
    h.get_by_role_and_label(Role::Slider, "Age (years)")
        .set_value_accesskit(4.0);
    h.step();
    assert!(diff(h.state().preview_image().unwrap(), &now).is_empty());
    // Play runs through the years and stops at the end.
    click(&mut h, "Play");
    assert!(h.state().controller().preview().is_playing());
    let start = Instant::now();
    while h.state().controller().preview().is_playing() {
        assert!(start.elapsed() < Duration::from_secs(30), "never stopped");
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(h.state().controller().preview().age_view(), None);
    assert_eq!(
        h.state().controller().preview().simulations(),
        simulations,
        "the simulation worker never started"
    );
}

#[test]
fn the_say_box_fills_the_sliders_and_shows_what_it_set() {
    let mut h = facade_with(quick_preset());
    h.get_by_role_and_label(Role::TextInput, "Say how old")
        .set_text_value_accesskit("very rusty near the railings, slightly scratched");
    h.step();
    h.get_by_label("Say it").click();
    h.step();
    h.step();
    let p = &h.state().document().unwrap().preset;
    assert!(p.rust.enabled && p.scratches.enabled);
    assert_eq!((p.rust.coverage, p.scratches.coverage), (0.55, 0.05));
    assert_eq!(p.say, "very rusty near the railings, slightly scratched");
    h.get_by_label("rust.coverage = 0.55");
    settle(&mut h);
    let preview = h.state().controller().preview().current().unwrap();
    let names: Vec<&str> = preview
        .stack
        .layers
        .iter()
        .map(|l| l.name.as_str())
        .collect();
    assert!(
        names.contains(&"rust") && names.contains(&"scratches"),
        "{names:?}"
    );
    // An unknown word shows the error instead and sets nothing more.
    h.get_by_role_and_label(Role::TextInput, "Say how old")
        .set_text_value_accesskit("very crusty");
    h.step();
    h.get_by_label("Say it").click();
    h.step();
    h.step();
    assert!(
        h.query_by_label_contains("unknown word \"crusty\"")
            .is_some()
    );
}

#[test]
fn auto_region_and_detect_ledges_come_from_the_scene_analysis() {
    let mut h = facade_with(quick_preset());
    let sample = h.state().document().unwrap().mask.clone();
    let proxy_site = |h: &Harness<'_, GrimeApp>| {
        let l = h.state().controller().loaded().unwrap();
        let job = l.proxy.job(&Preset::default(), None, &Default::default());
        (l.proxy.photo.width(), job.unwrap().scene.site)
    };
    let (pw, assumed) = proxy_site(&h);
    assert_eq!(
        assumed,
        grime::pipeline::Site::assumed(pw),
        "before any analysis the preview assumes a 10 m wall"
    );
    click(&mut h, "Clear");
    assert_eq!(mask_count(&h, 1), 0);
    click(&mut h, "Auto region");
    settle(&mut h);
    // The preview (and an export) now run with the site the analysis saw:
    // its scale, ground, ledges and shelter, as `grime run` does.
    let (_, seen) = proxy_site(&h);
    let photo = h.state().controller().loaded().unwrap().photo.clone();
    let a = grime::analysis::analyse(&photo, &Default::default()).unwrap();
    let ph = seen.shelter.as_ref().unwrap().height();
    assert_eq!(seen, grime::pipeline::Site::seen_at(&a, pw, ph));
    assert_ne!(seen.metres_per_pixel, assumed.metres_per_pixel);
    assert!(!seen.ledges.is_empty() && seen.ground.iter().any(|g| g.is_finite()));
    assert_eq!(
        h.state().controller().loaded().unwrap().site(),
        Some(grime::pipeline::Site::seen(&a))
    );
    // The sample's own region is the wall without sky and windows: the
    // analysis keeps all of that wall, and leaves out the sky and the glass
    // (it keeps window frames, which the sample cuts out with the glass).
    let mask = h.state().document().unwrap().mask.clone();
    let (wh, ht) = (mask.width(), mask.height());
    let lost = mask
        .iter()
        .zip(sample.iter())
        .filter(|&(a, b)| *a < 128 && *b >= 128)
        .count();
    assert!(lost * 100 < mask.len(), "{lost} wall pixels lost");
    assert_eq!(mask.get_pixel(wh / 2, 2)[0], 0, "the sky is not wall");
    for win in grime::demo::layout(wh, ht).windows {
        let (x, y) = (win.0 + (win.2 - win.0) / 4, (win.1 + win.3) / 2);
        assert!(mask.get_pixel(x, y)[0] < 128, "glass at {x},{y} is wall");
    }
    let auto = mask_count(&h, 128);

    // Editable with the eraser, and undone one step at a time.
    click(&mut h, "Eraser");
    drag(&mut h, (0.2, 0.5), (0.8, 0.5));
    assert!(mask_count(&h, 128) < auto);
    click(&mut h, "Undo");
    assert_eq!(mask_count(&h, 128), auto);
    click(&mut h, "Undo");
    assert_eq!(mask_count(&h, 1), 0, "auto region is one undo step");
    click(&mut h, "Redo");
    assert_eq!(mask_count(&h, 128), auto);

    // Detect ledges: the analysis's sills, cornice and roof line, once.
    click(&mut h, "Edit");
    click(&mut h, "Remove all source lines");
    assert!(h.state().document().unwrap().lines.is_empty());
    click(&mut h, "Detect ledges");
    settle(&mut h);
    let lines = h.state().document().unwrap().lines.clone();
    assert!(lines.len() >= 5, "{lines:?}");
    click(&mut h, "Detect ledges");
    settle(&mut h);
    assert_eq!(h.state().document().unwrap().lines, lines, "no repeats");
    click(&mut h, "Undo");
    assert!(h.state().document().unwrap().lines.is_empty());
    settle(&mut h);
}

#[test]
fn choices_points_and_lists_are_set_from_the_generic_panel() {
    use grime::preset::Placement;
    let mut h = facade_with(quick_preset());
    let preset = |h: &Harness<'static, GrimeApp>| h.state().document().unwrap().preset.clone();
    // A section no GUI code names: its word fields get a choice box from
    // the PARAMS table.
    h.get_by_label("Smudges").click_accesskit();
    h.run_steps(2);
    h.get_by_role_and_label(Role::ComboBox, "placement")
        .click_accesskit();
    h.run_steps(2);
    h.get_by_label("edges").click_accesskit();
    h.run_steps(2);
    assert_eq!(preset(&h).smudges.placement, Placement::Edges);
    assert!(!preset(&h).smudges.enabled, "only the placement changed");
    // The moss's colour and the dust's environment are choices too.
    h.get_by_role_and_label(Role::ComboBox, "color")
        .click_accesskit();
    h.run_steps(2);
    h.get_by_label("orange").click_accesskit();
    h.run_steps(2);
    assert_eq!(preset(&h).moss.color, grime::preset::MossColor::Orange);
    h.get_by_role_and_label(Role::ComboBox, "environment");
    // A point: one box per coordinate.
    let xs = h.get_all_by_role_and_label(Role::SpinButton, "around");
    assert_eq!(xs.count(), 2);
    h.get_all_by_role_and_label(Role::SpinButton, "around")
        .next()
        .unwrap()
        .set_value_accesskit(120.0);
    h.run_steps(2);
    assert_eq!(preset(&h).smudges.around, [120.0, 0.0]);
    // A polygon as TOML text, set on Enter; a wrong one is refused with
    // the preset's message and changes nothing.
    let area = || "[[0, 0], [200, 0], [200, 100]]";
    h.get_by_role_and_label(Role::TextInput, "area").focus();
    h.step();
    h.get_by_role_and_label(Role::TextInput, "area")
        .set_text_value_accesskit(area());
    h.step();
    h.key_press(Key::Enter);
    h.run_steps(2);
    assert_eq!(preset(&h).smudges.area.len(), 3);
    h.get_by_role_and_label(Role::TextInput, "area").focus();
    h.step();
    h.get_by_role_and_label(Role::TextInput, "area")
        .set_text_value_accesskit("[[0, 0], oops");
    h.step();
    h.key_press(Key::Enter);
    h.run_steps(2);
    assert_eq!(preset(&h).smudges.area.len(), 3);
    assert!(
        error_message(&h).contains("smudges.area"),
        "{}",
        error_message(&h)
    );
    // Each is one undo step.
    click(&mut h, "Undo");
    assert!(preset(&h).smudges.area.is_empty());
    settle(&mut h);
}
