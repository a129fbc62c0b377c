//! Rain and its stain: the water simulation's parameters (Chang, Yoshida
//! & Mukai eqs. 1-17) and how each rainfall's dirt is drawn onto the photo.

use serde::{Deserialize, Serialize};

/// A polyline in photo pixel coordinates that water drips from.
pub type SourceLine = Vec<[f32; 2]>;

/// Rain parameters. Symbols follow Chang, Yoshida & Mukai.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RainParams {
    /// Number of rainfalls (layers).
    pub layers: u32,
    /// Droplets per layer on a wall `reference_width` grid pixels wide.
    pub droplets: u32,
    /// Wall width the droplet count refers to; 0 = use `droplets` as is.
    pub reference_width: u32,
    /// Upper bound of the first layer's droplet mass, m ~ U(0, mass_max).
    pub mass_max: f32,
    /// Droplets lighter than this are removed.
    pub mass_min: f32,
    /// Spread of droplet mass and start position between layers (eqs. 16-17).
    pub sigma: f32,
    /// Wall absorption rate k_a (eqs. 5-6).
    pub k_a: f32,
    /// Deposition rate k_S; dissolution k_D = 1 - k_S (eqs. 7-8).
    pub k_s: f32,
    /// Saturation a: water one grid pixel can hold.
    pub saturation: f32,
    /// Evaporation I_sun per diffusion round, per pixel.
    pub i_sun: f32,
    /// User roughness r (eqs. 3-4).
    pub r: f32,
    /// Largest roughness r_max.
    pub r_max: f32,
    /// Sideways scatter constant b (eq. 2).
    pub b: f32,
    /// Gravity g, grid px per step squared.
    pub g: f32,
    /// Wall resistance rho (eq. 4).
    pub rho: f32,
    /// Speed limit, grid px per step (keeps streaks gap-free).
    pub v_max: f32,
    /// Exchange time per step for eqs. 5-8.
    pub dt: f32,
    /// Safety cap on steps per droplet.
    pub max_steps: u32,
    /// Amplitude of the initial dirt I_D0 (noise in 0..initial_dirt).
    /// [choice] Chang's Table 1 draws I_D0 in 0..5; here it is fresh grime
    /// added before every rainfall (eq. 12), and at 5 the droplets dissolve
    /// and re-deposit so much of it that blotches drown the streaks, so the
    /// default is 2 (`chang-table1` keeps 5).
    pub initial_dirt: f32,
    /// Feature size of the initial-dirt noise, in grid pixels.
    pub initial_dirt_scale: f32,
    /// Dirt a droplet carries when it leaves its source (washed off the ledge).
    pub ledge_dirt: f32,
    /// Carry-over rate delta between layers (eqs. 13-14).
    pub delta: f32,
    /// Surface raise eps from deposited dirt, fraction of full scale (eq. 15).
    pub eps: f32,
    /// Diffusion rate tau per neighbour (eqs. 9-10); at most 1/8.
    pub tau: f32,
    /// Diffusion rounds per layer, spread evenly over its droplets
    /// [choice: one, after the rainfall's droplets; Chang diffuses every
    /// time step and leaves the iteration count open].
    pub diffusion_rounds: u32,
    /// Relaxation iterations per round.
    pub diffusion_iterations: u32,
    /// How strongly dirt follows diffusing water, 0..1.
    pub dirt_coupling: f32,
    /// Whether the top edge of the region is a water source.
    pub top_edge: bool,
    /// Extra water sources: polylines in photo pixels (sills, cornices).
    pub source_lines: Vec<SourceLine>,
    /// Mean spacing of the drip points along a ledge, metres; 0 = water
    /// leaves anywhere along it (Chang's uniform start).
    pub drip_spacing_m: f32,
    /// Share of a ledge's water released at its two ends, 0..1.
    pub end_share: f32,
    /// Width of a release point (a streak's width at its top), metres.
    pub release_width_m: f32,
    /// Fall over which a streak's darkness fades (to a tenth), metres;
    /// 0 = no fading. Under drip points it follows each point's water,
    /// from a third to 4/3 of this (`effects::rain::fall`).
    pub fall_m: f32,
    /// A found ledge's confidence at which its streaks show in full; less
    /// sure ledges show theirs in proportion (`effects::rain::fall`); 0 = all.
    pub sure_at: f32,
    /// How unequal the streaks' strength is: the power of each release
    /// point's water (times its ledge's drain) its stain follows, so a few
    /// streaks are strong and most faint (`effects::rain::sources`); 0 =
    /// every streak at full strength.
    pub uneven: f32,
    /// Whether a streak's strength (`uneven`) and its ledge's sureness
    /// (`sure_at`) scale its stain after the dirt film rather than the
    /// coverage before it, so its final darkness follows them in
    /// proportion instead of only its length (`effects::rain::fall`).
    pub after_film: bool,
    /// Whether twin ledges (like windows in a row or a column) drain alike
    /// and share one sureness, each keeping its own drips
    /// (`effects::rain::twins`); off = every ledge its own.
    pub twins: bool,
    /// Whether each ledge sheds its water its own way: one end lower than
    /// the other, its own drip points' spacing and width, a soft wash under
    /// some (`effects::rain::habit`); off = every ledge about one mean.
    pub habits: bool,
    /// Whether a sure ledge catches the water running down to it from a
    /// source above, so the streaks from above stop on it instead of
    /// running on below it (`effects::rain::breaks`).
    pub breaks: bool,
    /// The shortest run of water between two breaks, metres: a ledge
    /// catches the water from above only where the nearest source above
    /// it lies at least this far up, so no short piece of run is left
    /// between two breaks (`effects::rain::breaks::RUN_M`; 0 = every
    /// sure ledge with a source above catches).
    pub break_run_m: f32,
}

impl Default for RainParams {
    fn default() -> Self {
        RainParams {
            layers: 12,
            droplets: 600,
            reference_width: 1000,
            mass_max: 120.0,
            mass_min: 0.5,
            sigma: 10.0,
            k_a: 0.5,
            k_s: 0.7,
            saturation: 0.3,
            i_sun: 0.01,
            r: 100.0,
            r_max: 100.0,
            b: 0.02,
            g: 0.15,
            rho: 3.0,
            v_max: 1.0,
            dt: 0.01,
            max_steps: 20_000,
            initial_dirt: 2.0,
            initial_dirt_scale: 48.0,
            ledge_dirt: 3.0,
            delta: 0.01,
            eps: 0.3,
            tau: 0.1,
            diffusion_rounds: 1,
            diffusion_iterations: 3,
            dirt_coupling: 0.5,
            top_edge: true,
            source_lines: Vec::new(),
            drip_spacing_m: 0.9,
            end_share: 0.5,
            release_width_m: 0.06,
            fall_m: 1.5,
            sure_at: crate::effects::rain::fall::SURE_AT,
            uneven: 1.0,
            after_film: true,
            twins: true,
            habits: true,
            breaks: true,
            break_run_m: crate::effects::rain::breaks::RUN_M,
        }
    }
}

/// How each rainfall's dirt is drawn onto the photo.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StainParams {
    /// Colour of the dirt, sRGB.
    pub color: [u8; 3],
    /// Opacity of each rain layer.
    pub opacity: f32,
    /// Stain strength: alpha = strength * D / D_max.
    pub strength: f32,
    /// Percentile of the first rainfall's deposits that defines D_max.
    pub percentile: f32,
    /// Blur radius of the stain edge, grid pixels.
    pub softness: f32,
    /// Blur radius of the stain edge, metres (added to `softness`).
    pub blur_m: f32,
    /// Colour the washed runs lighten toward, sRGB (screen blend).
    pub washed_color: [u8; 3],
    /// Opacity of the washed-runs layer; 0 = no such layer.
    pub washed_opacity: f32,
    /// Share of a full soot film laid under eaves, cornices and balconies
    /// between two rainfalls (the rain shelter); 0 = none.
    pub soot: f32,
    /// The rain's dirt as a deposit painted over the wall (hiding its grain
    /// where thick), with this share of the local wall's own chroma (the
    /// rest `color`'s); 0 = `color` multiplied onto the wall (Chang's).
    pub wall_hue: f32,
    /// The stain's grain (`effects/rain/texture.rs`): the deviation of a
    /// gain on each rainfall's alpha; 0 = smooth, the default (at 0.3 blind
    /// check p25 found its stripes under cornices a comb of drips).
    pub texture: f32,
    /// How far above the region's lower edges the stains run out, metres
    /// (a log-normal length about it, differing from streak to streak);
    /// 0 = they stop at the edge.
    pub run_out_m: f32,
}

impl Default for StainParams {
    fn default() -> Self {
        StainParams {
            color: [86, 76, 62],
            opacity: 0.25,
            strength: 0.6,
            percentile: 0.99,
            softness: 0.0,
            blur_m: 0.03,
            washed_color: [200, 196, 186],
            washed_opacity: 0.35,
            soot: crate::effects::rain::soot::PER_RAINFALL,
            wall_hue: 0.6,
            texture: 0.0,
            run_out_m: 0.3,
        }
    }
}
