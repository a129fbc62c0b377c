//! The rain, moss and dust as pipeline stages: each turns its simulation's
//! result into layers and stats (see [`super::Effect::run`]).

use std::sync::Arc;

use image::GrayImage;
use serde::Serialize;

use super::moss::{self, MossInput, Wet};
use super::rain::{self, RainInput, sources::Release};
use super::{Context, Effect, Produced, Products, Stats, climate, dust, habitat, surface};
use crate::error::Result;
use crate::field::{ColumnMajor, RowMajor};
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::{BlendMode, Layer, LayerPixels};

/// The rain's numbers for the whole run (per rainfall: the layers' own).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RainStats {
    /// Droplets per rainfall.
    pub droplets_per_layer: u32,
    /// D_max the stains are measured against.
    pub d_max: f32,
}

/// A layer of `effect` at full opacity setting `opacity`, visible.
fn layer(
    effect: Effect,
    name: String,
    opacity: f32,
    blend: BlendMode,
    pixels: LayerPixels,
) -> Layer {
    Layer {
        name,
        kind: Some(effect),
        blend,
        opacity,
        visible: true,
        pixels,
    }
}

/// The rainfalls (Chang eqs. 2-17) and one stain layer per rainfall.
pub(super) fn rain(
    ctx: &Context,
    products: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    let grid = ctx.grid;
    let r = &preset.rain;
    let lines = grid_lines(ctx, r);
    // The region the droplets run on, cut above the sure ledges.
    let ran_on = r.breaks.then(|| catchers(ctx, r, &lines)).flatten();
    let input = RainInput {
        luma: ctx.luma,
        region: ran_on.as_ref().unwrap_or(ctx.region),
        source_lines: lines,
        catch: r.source_lines.iter().map(|l| catch(ctx, l)).collect(),
        release: release(ctx, r),
        washed: preset.stain.washed_opacity > 0.0,
    };
    let (mut out, mut kept) = rain::simulate_keeping(
        &input,
        r,
        preset.seed,
        &progress.span(0.0, 0.87),
        &products.keep_rain_at,
    )?;
    if let Some(cut) = &ran_on {
        let maps = [&mut out.water, &mut out.dirt].into_iter();
        let kept_maps = kept.iter_mut().flat_map(|k| [&mut k.water, &mut k.dirt]);
        maps.chain(kept_maps)
            .for_each(|m| rain::breaks::fill(m, ctx.region, cut));
    }
    let (out, kept) = (Arc::new(out), kept.into_iter().map(Arc::new).collect());
    let mut stainer = Stainer::new(ctx, preset);

    let d_max = rain::stain::d_max(&out.layers, preset.stain.percentile);
    let mut layers = Vec::with_capacity(out.layers.len() + 1);
    let mut layer_stats = Vec::with_capacity(out.layers.len() + 1);
    let stain = &preset.stain;
    // The deposit's colour, the same for every rainfall.
    let deposit = (stain.wall_hue > 0.0 && !out.layers.is_empty())
        .then(|| Arc::new(rain::deposit::colors(ctx, stain.color, stain.wall_hue)));
    for (i, rl) in out.layers.iter().enumerate() {
        progress.check()?;
        progress.update("stain", 0.87 + 0.13 * i as f32 / out.layers.len() as f32);
        let alpha = stainer.rainfall(&rl.deposit, d_max);
        let (pixels, blend) = match &deposit {
            Some(color) => (
                LayerPixels::Painted {
                    color: Arc::clone(color),
                    alpha,
                },
                BlendMode::Normal,
            ),
            None => (
                LayerPixels::Tint {
                    color: stain.color,
                    alpha,
                },
                BlendMode::Multiply,
            ),
        };
        let name = format!("rain {:02}", i + 1);
        layers.push(layer(Effect::Rain, name, stain.opacity, blend, pixels));
        layer_stats.push(Some(rl.stats.clone()));
    }
    if let Some(washed) = &out.washed {
        layers.push(stainer.washed(washed));
        layer_stats.push(None);
    }
    products.rain_kept = kept;
    products.rain = Some(out);
    Ok(Produced {
        layers,
        layer_stats,
        stats: Stats::Rain(RainStats {
            droplets_per_layer: rain::droplet_count(&preset.rain, grid.width),
            d_max,
        }),
    })
}

/// Name of the rain's washed-runs layer, above its rainfalls.
pub const WASHED: &str = "rain washed";

/// The source lines on the grid.
fn grid_lines(ctx: &Context, r: &crate::preset::RainParams) -> Vec<Vec<(f32, f32)>> {
    r.source_lines
        .iter()
        .map(|line| line.iter().map(|p| ctx.grid.to_grid(p[0], p[1])).collect())
        .collect()
}

/// The region the droplets run on when sure ledges catch the water from
/// above ([`rain::breaks::cut`]); `None` when nothing is cut.
fn catchers(
    ctx: &Context,
    r: &crate::preset::RainParams,
    lines: &[Vec<(f32, f32)>],
) -> Option<crate::field::RowMajor<bool>> {
    let ledges: Vec<_> = lines
        .iter()
        .zip(&r.source_lines)
        .map(|(line, photo)| rain::breaks::Catcher {
            line,
            sure: rain::fall::sure(confidence(found(ctx, photo)), r.sure_at),
        })
        .collect();
    let (course, run) = (
        ctx.grid_px(rain::breaks::COURSE_M),
        ctx.grid_px(r.break_run_m),
    );
    rain::breaks::cut(ctx.region, ctx.luma, &ledges, r.top_edge, course, run)
}

/// Where ledges release their water, in grid pixels.
fn release(ctx: &Context, r: &crate::preset::RainParams) -> Release {
    Release {
        spacing: ctx.grid_px(r.drip_spacing_m),
        width: ctx.grid_px(r.release_width_m),
        end_share: r.end_share,
        uneven: r.uneven,
        habits: r.habits,
    }
}

/// The washed-runs layer of a rain whose net washed dirt is `washed`
/// ([`rain::RainOutput::washed`]): what a time-lapse frame shows after its
/// own rainfalls, from the wall the run kept then.
pub fn washed_layer(ctx: &Context, preset: &Preset, washed: &ColumnMajor<f32>) -> Layer {
    Stainer::new(ctx, preset).washed(washed)
}

/// From the rain's grid maps to photo-sized stain alphas: blurred, faded
/// and widened down the fall below the sources.
struct Stainer<'a> {
    ctx: &'a Context<'a>,
    preset: &'a Preset,
    /// [`rain::fall::fade`].
    fall: rain::fall::Fall,
    /// The stain edge's blur, grid pixels.
    blur: f32,
    /// The blur at the end of the fall; `None` = no fall.
    wider: Option<f32>,
    /// Whether the streaks' strength and sureness scale the film's
    /// alpha rather than the coverage (`rain.after_film`).
    after: bool,
    /// [`rain::fall::Fall::gain`], wandered like the streaks, when it is
    /// laid after the film and is not 1 everywhere streaks run.
    gain: Option<RowMajor<f32>>,
    /// The factor on one rainfall's alpha after the film (the gain, the
    /// soot's share kept whole).
    scale: RowMajor<f32>,
    coverage: rain::stain::Coverage,
    widened: rain::stain::Coverage,
    /// The film the rainfalls so far laid.
    film: rain::stain::Film,
    /// How runs wander sideways on this wall.
    wander: rain::wander::Wander,
    /// The soot laid in the rain shelter between rainfalls, made for the
    /// first rainfall (a washed layer alone needs none).
    soot: Option<rain::soot::Soot>,
    /// The stains' grain and run-out ([`rain::texture`]), made for the
    /// first rainfall; `None` when both are off.
    texture: Option<Option<rain::texture::Texture>>,
    /// Where a deposit shows ([`rain::soak`]), made for the first
    /// rainfall when the dirt is a deposit (`stain.wall_hue`).
    soak: Option<rain::soak::Soak>,
}

impl<'a> Stainer<'a> {
    /// The stainer of `preset`'s rain on `ctx`'s grid.
    fn new(ctx: &'a Context<'a>, preset: &'a Preset) -> Stainer<'a> {
        let (grid, r) = (ctx.grid, &preset.rain);
        let release = release(ctx, r);
        let top_edge = r.top_edge.then(|| top_rows(ctx.region));
        let lines = grid_lines(ctx, r);
        let found: Vec<_> = r.source_lines.iter().map(|l| found(ctx, l)).collect();
        let kinds: Vec<_> = found.iter().map(|l| l.map(|l| l.kind)).collect();
        let sure: Vec<_> = found
            .iter()
            .map(|l| rain::fall::sure(confidence(*l), r.sure_at))
            .collect();
        let twins = rain::twins::Twins::new(preset.seed, &r.source_lines, &kinds, &sure, r.twins);
        // The drip points the rain released its water from.
        let warps: Vec<_> = lines
            .iter()
            .enumerate()
            .map(|(i, line)| {
                let len = rain::sources::Source::line(rain::padded(line)).length();
                let key = rain::sources::line_key(line);
                twins.warp(i, rain::sources::line_warp(preset.seed, key, len, &release))
            })
            .collect();
        let ledges: Vec<_> = lines
            .iter()
            .zip(&warps)
            .zip(r.source_lines.iter().zip(twins.sure(&sure)))
            .map(|((line, warp), (photo, sure))| rain::fall::Ledge {
                line,
                warp: warp.as_ref(),
                catch: catch(ctx, photo),
                sure,
            })
            .collect();
        let caught = r
            .breaks
            .then(|| rain::breaks::caught(ctx.luma, ctx.region, ctx.grid_px(1.0)));
        let fall = rain::fall::fade(
            grid.width,
            grid.height,
            &ledges,
            top_edge.as_deref(),
            ctx.grid_px(r.fall_m),
            3.0 * release.width,
            ctx.grid_px(ONSET_M),
            caught.as_ref().map(|sum| rain::fall::Caught {
                sum,
                run: ctx.grid_px(r.break_run_m),
            }),
        );
        let blur = preset.stain.softness + ctx.grid_px(preset.stain.blur_m);
        let wander =
            rain::wander::Wander::new(preset.seed, grid.width, grid.height, ctx.grid_px(1.0));
        let after = r.after_film;
        let gain = after
            .then(|| rain::fall::gain_where_it_runs(&fall))
            .flatten()
            .map(|mut gain| {
                wander.apply(&mut gain);
                gain
            });
        Stainer {
            ctx,
            preset,
            fall,
            blur,
            wider: (r.fall_m > 0.0).then_some(blur + ctx.grid_px(SPREAD_M)),
            coverage: rain::stain::Coverage::new(grid.width, grid.height),
            widened: rain::stain::Coverage::new(grid.width, grid.height),
            film: rain::stain::Film::new(grid.width, grid.height),
            wander,
            after,
            scale: RowMajor::filled(
                if gain.is_some() { grid.width } else { 0 },
                grid.height,
                1.0,
            ),
            gain,
            soot: None,
            texture: None,
            soak: None,
        }
    }

    /// The alpha of the next rainfall's layer, from its `deposit` measured
    /// against `d_max` and the soot laid in the shelter since the last one,
    /// laid on the film of the rainfalls before it.
    fn rainfall(&mut self, deposit: &ColumnMajor<f32>, d_max: f32) -> GrayImage {
        self.alpha(deposit, d_max, true)
    }

    /// The alpha of `values` measured against `max`, laid on the rain's
    /// film when `film`.
    fn alpha(&mut self, values: &ColumnMajor<f32>, max: f32, film: bool) -> GrayImage {
        let stain = &self.preset.stain;
        let cover = self.coverage.of(values, max, stain, self.blur);
        let fade = self.fall.before_film(self.after);
        match self.wider {
            Some(wider) => {
                let wide = self.widened.of(values, max, stain, wider);
                rain::fall::widen(cover, wide, fade, &self.fall);
            }
            // No fall: the stain as it is, below the sources.
            None => rain::stain::scale(cover, fade),
        }
        self.wander.apply(cover);
        if let Some(gain) = &self.gain {
            self.scale.data_mut().copy_from_slice(gain.data());
        }
        if film {
            let (ctx, preset) = (self.ctx, self.preset);
            if preset.stain.soot > 0.0 {
                let soot = self.soot.get_or_insert_with(|| {
                    rain::soot::Soot::new(
                        preset.seed,
                        preset.stain.soot,
                        &habitat::below_projections(ctx, rain::soot::TAPER_M),
                        ctx.grid_px(1.0),
                    )
                });
                match self.gain.is_some() {
                    true => soot.lay_gained(cover, &mut self.scale),
                    false => soot.lay(cover),
                }
            }
            self.film.lay(cover);
            if self.gain.is_some() {
                rain::stain::scale(cover, &self.scale);
            }
            let texture = self.texture.get_or_insert_with(|| {
                rain::texture::Texture::new(
                    preset.seed,
                    ctx.region,
                    ctx.grid_px(1.0),
                    preset.stain.texture,
                    preset.stain.run_out_m,
                )
            });
            if let Some(texture) = texture {
                texture.apply(cover);
            }
            if preset.stain.wall_hue > 0.0 {
                let soak = self
                    .soak
                    .get_or_insert_with(|| rain::soak::Soak::new(ctx, preset.seed));
                let (w, h) = ctx.size();
                let mut alpha = ctx.grid.upsample(cover, None, w, h);
                soak.lay(&mut alpha, ctx.mask);
                return alpha;
            }
        } else if self.gain.is_some() {
            rain::stain::scale(cover, &self.scale);
        }
        let (w, h) = self.ctx.size();
        self.ctx.grid.upsample(cover, self.ctx.mask, w, h)
    }

    /// The washed runs: where droplets dissolved more dirt than they ever
    /// left (Chang eqs. 7-8 with a negative net deposit, summed over the
    /// rainfalls), lighter where more was washed off [choice: net, so a
    /// washed run never lightens a streak the rain stained; measured
    /// against its own high percentile, like D_max; screened toward
    /// `stain.washed_color`, the clean stone under the soot].
    fn washed(&mut self, washed: &ColumnMajor<f32>) -> Layer {
        let max = rain::stain::w_max(washed, self.preset.stain.percentile);
        let pixels = LayerPixels::Tint {
            color: self.preset.stain.washed_color,
            alpha: self.alpha(washed, max, false),
        };
        layer(
            Effect::Rain,
            WASHED.into(),
            self.preset.stain.washed_opacity,
            BlendMode::Screen,
            pixels,
        )
    }
}

/// The ledge the analysis found along `line` (photo pixels, as in
/// `rain.source_lines`): the site's ledge with the same vertices (within
/// half a pixel, so a preview's scaled lines match); `None` for a line the
/// analysis did not find (a preset's or the user's own).
fn found<'a>(ctx: &'a Context, line: &[[f32; 2]]) -> Option<&'a crate::analysis::Ledge> {
    let same = |l: &crate::analysis::Ledge| {
        l.polyline.len() == line.len()
            && l.polyline
                .iter()
                .zip(line)
                .all(|(a, b)| (a[0] - b[0]).abs() <= 0.5 && (a[1] - b[1]).abs() <= 0.5)
    };
    ctx.site.ledges.iter().find(|l| same(l))
}

/// The analysis's confidence in a `found` ledge; 1 for a line it did not
/// find.
fn confidence(found: Option<&crate::analysis::Ledge>) -> f32 {
    found.map_or(1.0, |l| l.confidence.clamp(0.0, 1.0))
}

/// How much rain a ledge (a polyline in photo pixels) catches: 1 minus the
/// scene's rain shelter just above it, averaged along it (`how-facades-age.md`:
/// the wall under a projecting cornice, balcony or eave stays dry).
fn catch(ctx: &Context, line: &[[f32; 2]]) -> f32 {
    let above = ctx.photo_px(CATCH_ABOVE_M).max(1.0);
    let (mut sum, mut n) = (0.0, 0);
    for pair in line.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let steps = (b[0] - a[0]).hypot(b[1] - a[1]).ceil().max(1.0) as usize;
        for k in 0..steps {
            let t = k as f32 / steps as f32;
            let (x, y) = (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t - above);
            sum += ctx.site.shelter_at(x.max(0.0) as u32, y.max(0.0) as u32);
            n += 1;
        }
    }
    if n == 0 { 1.0 } else { 1.0 - sum / n as f32 }
}

/// How far below a ledge its drips' streaks begin, up to, and then darken
/// over, metres [choice: water leaving a drip point falls free a little
/// before it meets the wall; 0.05 m, so the streaks' tops under a string
/// course spread over a few centimetres instead of one straight dark line
/// (blind review 13); 0.08 m left a visible clean gap under each ledge on
/// the one-ledge wall].
const ONSET_M: f32 = 0.05;

/// How far a streak has spread sideways by half its fall and below,
/// metres: the standard deviation the blur it has widened into there adds
/// to the stain's edge blur ([`rain::fall::SPREAD_BY`]) [choice: 0.2 m;
/// `how-facades-age.md`: "narrow at the release point, wider and fainter
/// over a fall of about 0.5 to 2 m". 0.15 m until the twenty-third pass,
/// reached only at the fall's end. On the one-ledge wall
/// (`tests/streaks.rs`, `streaks_widen_downward_not_to_a_tip`, three
/// seeds) the ink of the forty rainfalls is
/// 126176 on main, 127983 at 0.15, 123752 at 0.2 (-1.9%), 119312 at 0.25
/// (-5.4%: the widest washes' per-layer alphas round to 0 in 8 bits); the
/// width over half a row's darkest at 80% of a streak's length 20.6
/// columns on main, 37.3 at 0.15, 42.8 at 0.2, 44.2 at 0.25].
const SPREAD_M: f32 = 0.2;

/// Where a ledge's catch is read: this far above it, on its top, metres.
const CATCH_ABOVE_M: f32 = 0.05;

/// The first region row of each grid column (the top-edge source).
fn top_rows(region: &crate::field::RowMajor<bool>) -> Vec<Option<usize>> {
    (0..region.width())
        .map(|x| (0..region.height()).find(|&y| region.get(x, y)))
        .collect()
}

/// A rain layer follows the preset's stain colour and opacity, and shows
/// only the first `rain.layers` rainfalls; the washed runs follow their own
/// colour and opacity. A deposit's colour map stays (it follows
/// `stain.color` through a new run, [`super::Effect::restyles`]).
pub(super) fn restyle_rain(layer: &mut Layer, index: usize, preset: &Preset) {
    if layer.name == WASHED {
        layer.opacity = preset.stain.washed_opacity;
        if let LayerPixels::Tint { color, .. } = &mut layer.pixels {
            *color = preset.stain.washed_color;
        }
        return;
    }
    layer.opacity = preset.stain.opacity;
    if let LayerPixels::Tint { color, .. } = &mut layer.pixels {
        *color = preset.stain.color;
    }
    layer.visible = index < preset.rain.layers as usize;
}

/// The "moss" layer (Chang eq. 18), grown from the rain's final water and
/// dirt, or (with no rainfall) from the preset's humidity.
pub(super) fn moss(
    ctx: &Context,
    products: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    let rain = products.rain.clone();
    let wet = rain
        .as_deref()
        .filter(|r| !r.layers.is_empty())
        .map(|r| Wet {
            water: &r.water,
            saturation: preset.rain.saturation,
            dirt: &r.dirt,
            d_max: moss::d_max(&r.dirt, ctx.region, preset.stain.percentile),
        });
    let p = &preset.moss;
    let climate = (p.by_humidity != 0.0).then(|| products.climate(ctx, &preset.climate));
    let make = || {
        let humid = encouragement(ctx, climate.as_deref(), p.by_humidity, |c| &c.humidity);
        moss_habitat(ctx, preset, humid)
    };
    let made;
    let habitat = match products.carry.as_deref_mut() {
        Some(carry) => carry.habitat(preset, make),
        None => {
            made = make();
            &made
        }
    };
    let baseline = match p.baseline > 0.0 {
        true => p.baseline * ctx.grid.box_w as f32,
        false => ctx.photo_px(p.colony_m),
    };
    let input = MossInput {
        luma: ctx.luma,
        region: ctx.region,
        wet,
        habitat: (p.open_wall < 1.0).then_some(habitat),
        baseline,
    };
    let mut grown = moss::grow(
        &input,
        ctx.grid,
        ctx.wall,
        &preset.moss,
        preset.seed,
        progress,
    )?;
    // [choice] Colonies a few pixels across (a street photo, centimetres
    // a pixel) are as soft as the photo's own detail: without this they are
    // crisp one-pixel specks, read as pasted sprites in the blind review.
    if baseline < SMALL_COLONY_PX {
        surface::soften(&mut grown.layer, PHOTO_SOFTNESS_PX, ctx.mask);
    }
    // Lit after the softening, so the wall's joints and grain stay sharp
    // through the colony (`surface::light`).
    let radius = ctx.grid_px(surface::light::LIGHT_M).round() as usize;
    let light = surface::light::Light::of(ctx.photo, ctx.grid, ctx.region, radius);
    surface::light::light(&mut grown.layer, ctx.photo, &light);
    let pixels = LayerPixels::Rgba(grown.layer);
    let layer = layer(
        Effect::Moss,
        "moss".into(),
        preset.moss.opacity,
        BlendMode::Normal,
        pixels,
    );
    Ok(Produced {
        layers: vec![layer],
        layer_stats: vec![None],
        stats: Stats::Moss(grown.stats),
    })
}

/// Where moss takes (see [`habitat`]): 1 in the splash zone, half that on
/// ledge tops, 0.7 in joints, `open_wall` on the rest of the wall; the
/// rain shelter stays dry (`how-facades-age.md`), so joints there do not
/// count. The climate's humidity then moves it (`humid`, by
/// `by_humidity`).
fn moss_habitat(ctx: &Context, preset: &Preset, humid: RowMajor<f32>) -> RowMajor<f32> {
    let (p, seed) = (&preset.moss, preset.seed);
    let mut map = habitat::splash(ctx, p.splash_m);
    let tops = habitat::ledge_tops(ctx, p.ledge_top_m);
    let joints = habitat::joints(ctx);
    let shelter = habitat::shelter(ctx);
    for (((v, t), j), s) in map
        .data_mut()
        .iter_mut()
        .zip(tops.data())
        .zip(joints.data())
        .zip(shelter.data())
    {
        *v = v.max(LEDGE_TOP * t).max(0.7 * j * (1.0 - s));
    }
    // [choice] Growth is patchy along a ledge or a wall's foot: fBm about
    // PATCH_M across scales the places from 0 (about a third of them bare)
    // to 1; a floor of 0.2 traced every ledge with an even dotted line.
    let (w, h) = (ctx.grid.width, ctx.grid.height);
    let key = crate::random::key(seed, (Effect::Moss, PATCHES), 0, 0);
    let noise = crate::random::Noise::new(key, w as u32, h as u32, ctx.grid_px(PATCH_M), 3);
    for (i, v) in map.data_mut().iter_mut().enumerate() {
        let patch = (3.0 * noise.at((i % w) as f32, (i / w) as f32) - 1.3).clamp(0.0, 1.0);
        *v = ((*v * humid.data()[i]).min(1.0) * patch).max(p.open_wall);
    }
    map
}

/// The climate's encouragement of an effect by one of its maps, weight
/// `k` (see [`climate::encouragement`]); 1 everywhere without a climate.
fn encouragement(
    ctx: &Context,
    climate: Option<&climate::Climate>,
    k: f32,
    map: impl FnOnce(&climate::Climate) -> &RowMajor<f32>,
) -> RowMajor<f32> {
    match climate {
        Some(c) => climate::encouragement(map(c), ctx.region, k),
        None => RowMajor::filled(ctx.grid.width, ctx.grid.height, 1.0),
    }
}

/// Colonies narrower than this many pixels are softened.
const SMALL_COLONY_PX: f32 = 4.0;

/// A photo's own blur at its finest detail (lens, demosaicing, JPEG),
/// pixels: the Gaussian small colonies are softened by.
const PHOTO_SOFTNESS_PX: f32 = 0.8;

/// How much moss a ledge top takes against the splash zone [choice: from
/// the street a ledge above the camera shows only its front lip, and a
/// full share traced every ledge in the blind review].
const LEDGE_TOP: f32 = 0.5;

/// Size of the patches moss keeps to along its places, metres.
const PATCH_M: f32 = 0.5;

/// The moss's own stream for its patches.
const PATCHES: u16 = 1;

/// The "dust film" and "dust granules" layers (Santos & Baranoski), at the
/// scene's scale, settled where rain does not wash: on ledge tops and in
/// rain shelter, `open_wall` as much on the rest.
pub(super) fn dust(
    ctx: &Context,
    products: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    let p = &dust::at_scale(&preset.dust, ctx.site.metres_per_pixel);
    let (mut film, mut granules, stats) = match products.carry.as_deref_mut() {
        Some(carry) => carry.dust(ctx.wall, ctx.normals, p, preset.seed, progress)?,
        None => dust::accumulate(ctx.wall, ctx.normals, p, preset.seed, progress)?,
    };
    if p.open_wall < 1.0 {
        let climate = (p.by_light != 0.0).then(|| products.climate(ctx, &preset.climate));
        let make = || {
            let light = encouragement(ctx, climate.as_deref(), p.by_light, |c| &c.light);
            dust::settle::map(ctx, p, preset.seed, light)
        };
        let made;
        let settle = match products.carry.as_deref_mut() {
            Some(carry) => carry.settle(p, &preset.climate, make),
            None => {
                made = make();
                &made
            }
        };
        dust::settle::apply(film.as_mut(), 4, settle);
        dust::settle::apply(granules.as_mut(), 1, settle);
    }
    // [choice] The film darkens the wall by its grey (multiply): soot on a
    // facade keeps the surface's texture and darkens a dark brick as it
    // does a light render. Painted over as Santos' eq. (11) says, the grey
    // (70-110) lightened dark walls and hardly showed on mid ones (measured:
    // ledge tops 2.5 luma darker over 10 LMF photos, two of them lighter).
    let film = LayerPixels::Rgba(film);
    let granules = LayerPixels::Tint {
        color: p.granule_color,
        alpha: granules,
    };
    let normal = BlendMode::Normal;
    Ok(Produced {
        layers: vec![
            layer(
                Effect::Dust,
                "dust film".into(),
                p.film_opacity,
                BlendMode::Multiply,
                film,
            ),
            layer(
                Effect::Dust,
                "dust granules".into(),
                p.granule_opacity,
                normal,
                granules,
            ),
        ],
        layer_stats: vec![None, None],
        stats: Stats::Dust(stats),
    })
}
