//! The one table of parameter meanings and ranges.

/// One tunable number: its dotted path, paper symbol, meaning and range.
#[derive(Debug, Clone, Copy)]
pub struct ParamSpec {
    /// Dotted path in the preset, e.g. `rain.k_a`.
    pub path: &'static str,
    /// The paper's symbol, or "" if the paper has none.
    pub symbol: &'static str,
    /// What it does, in one sentence (also the GUI tooltip).
    pub doc: &'static str,
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
    /// The words a string field takes (the GUI's choice box); empty for
    /// numbers, switches and free text.
    pub choices: &'static [&'static str],
}

impl ParamSpec {
    /// The same row for a field that takes one of `choices`.
    pub(super) const fn choices(self, choices: &'static [&'static str]) -> ParamSpec {
        ParamSpec { choices, ..self }
    }
}

pub(super) const fn p(
    path: &'static str,
    symbol: &'static str,
    doc: &'static str,
    min: f64,
    max: f64,
) -> ParamSpec {
    ParamSpec {
        path,
        symbol,
        doc,
        min,
        max,
        choices: &[],
    }
}

/// The core effects' parameters (rain, stain, moss, dust, γ-tons).
pub(super) const CORE: &[ParamSpec] = &[
    p(
        "seed",
        "",
        "Master random seed; the same seed gives byte-identical output",
        0.0,
        i64::MAX as f64,
    ),
    p(
        "age.years",
        "",
        "Age of the wall in years: sets rain.layers, moss.years and dust.days from the per-year rates of this section (those fields given on the command line, or written uncommented in the preset file, win)",
        0.0,
        250.0,
    ),
    p(
        "age.rainfalls_per_year",
        "",
        "Rainfalls (rain layers) per year of age",
        0.0,
        50.0,
    ),
    p(
        "age.moss_years_per_year",
        "",
        "Years of moss growth per year of age",
        0.0,
        10.0,
    ),
    p(
        "age.dust_days_per_year",
        "",
        "Days of dust settling per year of age (rain washes an outside wall: 365/15 gives the default year of dust at 15 years)",
        0.0,
        365.0,
    ),
    p(
        "sim.max_side",
        "",
        "Longest side of the simulation grid in pixels (0 = photo resolution); the streak pattern is computed on this grid and its stains are upsampled smoothly",
        0.0,
        16384.0,
    ),
    p(
        "rain.layers",
        "",
        "Number of rainfalls; each one is a layer (Chang sec. 3.2)",
        0.0,
        200.0,
    ),
    p(
        "rain.droplets",
        "n",
        "Droplets per rainfall on a wall reference_width grid pixels wide (Chang Table 1: 600)",
        0.0,
        100000.0,
    ),
    p(
        "rain.reference_width",
        "",
        "Wall width that `droplets` refers to; the count scales with the region's width. 0 = no scaling",
        0.0,
        100000.0,
    ),
    p(
        "rain.mass_max",
        "m",
        "First-layer droplet mass is uniform in 0..mass_max (Chang Table 1: 0..120)",
        0.001,
        10000.0,
    ),
    p(
        "rain.mass_min",
        "",
        "A droplet lighter than this is removed and leaves its dirt behind",
        0.0,
        1000.0,
    ),
    p(
        "rain.sigma",
        "sigma",
        "Spread of droplet mass and start position from one rainfall to the next (eqs. 16-17)",
        0.0,
        1000.0,
    ),
    p(
        "rain.k_a",
        "k_a",
        "Wall absorption rate: how fast the wall soaks up a droplet's water (eqs. 5-6)",
        0.0,
        1.0,
    ),
    p(
        "rain.k_s",
        "k_S",
        "Dirt deposition rate; the dissolution rate is k_D = 1 - k_S (eqs. 7-8)",
        0.0,
        1.0,
    ),
    p(
        "rain.saturation",
        "a",
        "Water one grid pixel can hold; lower = longer streaks",
        0.001,
        1000.0,
    ),
    p(
        "rain.i_sun",
        "I_sun",
        "Evaporation of wall water per diffusion round, over the whole wall (eq. 6)",
        0.0,
        1000.0,
    ),
    p(
        "rain.r",
        "r",
        "Wall roughness chosen by the user; larger = more sideways scatter (eqs. 2-4)",
        0.0,
        1000.0,
    ),
    p(
        "rain.r_max",
        "r_max",
        "Largest roughness; the braking terms divide by r_max - r + 1",
        0.0,
        1000.0,
    ),
    p(
        "rain.b",
        "b",
        "Scatter constant of the sideways velocity b*r*xi*M_y (eq. 2)",
        0.0,
        1.0,
    ),
    p(
        "rain.g",
        "g",
        "Gravity in grid pixels per step squared (eq. 4)",
        0.0,
        10.0,
    ),
    p(
        "rain.rho",
        "rho",
        "Wall resistance: how much vertical roughness brakes the fall (eq. 4)",
        0.0,
        1000.0,
    ),
    p(
        "rain.v_max",
        "",
        "Speed limit in grid pixels per step; at most 1 keeps streaks gap-free",
        0.01,
        1.0,
    ),
    p(
        "rain.dt",
        "dt",
        "Time a droplet spends per step in the water and dirt exchange (eqs. 5-8); larger = shorter, darker streaks",
        0.0001,
        10.0,
    ),
    p(
        "rain.max_steps",
        "",
        "Safety cap on the steps of one droplet",
        1.0,
        10_000_000.0,
    ),
    p(
        "rain.initial_dirt",
        "I_D0",
        "Fresh grime per rainfall: smooth noise in 0..initial_dirt (Chang Table 1: 0..5)",
        0.0,
        1000.0,
    ),
    p(
        "rain.initial_dirt_scale",
        "",
        "Feature size of the fresh-grime noise, grid pixels",
        1.0,
        4096.0,
    ),
    p(
        "rain.ledge_dirt",
        "S_0",
        "Dirt a droplet washes off its ledge before it runs down the wall",
        0.0,
        1000.0,
    ),
    p(
        "rain.delta",
        "delta",
        "Carry-over of dirt from one rainfall into the next (eqs. 13-14)",
        0.0,
        1.0,
    ),
    p(
        "rain.eps",
        "eps",
        "How much deposited dirt raises the surface for the next rain, fraction of full scale (eq. 15)",
        0.0,
        1.0,
    ),
    p(
        "rain.tau",
        "tau",
        "Moisture diffusion rate to each of 8 neighbours; at most 1/8 keeps water non-negative (eqs. 9-10)",
        0.0,
        0.125,
    ),
    p(
        "rain.diffusion_rounds",
        "",
        "Diffusion rounds per rainfall, spread evenly over its droplets",
        0.0,
        1000.0,
    ),
    p(
        "rain.diffusion_iterations",
        "",
        "Relaxation iterations of eqs. 9-10 per round",
        0.0,
        1000.0,
    ),
    p(
        "rain.dirt_coupling",
        "",
        "How strongly dirt follows diffusing water (0 = dirt stays put, 1 = moves like water)",
        0.0,
        1.0,
    ),
    p(
        "rain.drip_spacing_m",
        "",
        "Mean spacing of the drip points along a ledge, metres; water gathers and leaves there, so streaks stand apart (0 = uniform, Chang's own)",
        0.0,
        100.0,
    ),
    p(
        "rain.end_share",
        "",
        "Share of a ledge's water that runs off its two ends: the pair of streaks under a sill",
        0.0,
        1.0,
    ),
    p(
        "rain.release_width_m",
        "",
        "Width of one release point, metres: how wide a streak starts",
        0.0,
        1.0,
    ),
    p(
        "rain.fall_m",
        "",
        "Fall below a ledge over which a streak fades to a tenth of its darkness, metres (0 = no fading)",
        0.0,
        100.0,
    ),
    p(
        "stain.color",
        "",
        "Colour of the rain dirt (sRGB), multiplied onto the wall",
        0.0,
        255.0,
    ),
    p("stain.opacity", "", "Opacity of each rain layer", 0.0, 1.0),
    p(
        "stain.strength",
        "",
        "Stain alpha = strength * D / D_max",
        0.0,
        10.0,
    ),
    p(
        "stain.percentile",
        "D_max",
        "Percentile of the first rainfall's deposits taken as D_max, so one hot pixel cannot wash out the rest",
        0.5,
        1.0,
    ),
    p(
        "stain.softness",
        "",
        "Blur radius of stain edges, grid pixels (added to stain.blur_m)",
        0.0,
        64.0,
    ),
    p(
        "stain.blur_m",
        "",
        "Blur radius of stain edges, metres",
        0.0,
        1.0,
    ),
    p(
        "stain.washed_color",
        "",
        "Colour the lighter washed runs (where droplets dissolved the wall's dirt) screen toward, sRGB",
        0.0,
        255.0,
    ),
    p(
        "stain.washed_opacity",
        "",
        "Opacity of the \"rain washed\" layer (0 = none)",
        0.0,
        1.0,
    ),
    p(
        "moss.enabled",
        "",
        "Grow moss (a \"moss\" layer above the rain layers)",
        0.0,
        0.0,
    ),
    p(
        "moss.years",
        "",
        "Years of moss growth: colonies seed, spread to their neighbours and grow every year",
        0.0,
        500.0,
    ),
    p(
        "moss.color",
        "",
        "Colony colour: \"orange\" RGB(180,130,0) or \"yellow-green\" RGB(140,130,80), Chang's two Caloplaca colours",
        0.0,
        0.0,
    )
    .choices(&["orange", "yellow-green"]),
    p(
        "moss.gamma",
        "gamma",
        "Moss probability factor of f = 1/2 (w/a + D/D_max) M_y gamma, f clamped to 0..1 (Chang eq. 18, Table 1: 1.5)",
        0.0,
        100.0,
    ),
    p(
        "moss.humidity",
        "",
        "Wetness standing in for (w/a + D/D_max)/2 when there is no rain, wetter toward the top of the wall",
        0.0,
        1.0,
    ),
    p(
        "moss.color_jitter",
        "",
        "Random change of each moss dot's R, G and B, in levels (Chang varies every dot)",
        0.0,
        255.0,
    ),
    p("moss.opacity", "", "Opacity of the moss layer", 0.0, 1.0),
    p(
        "moss.baseline",
        "",
        "Length of a colony's fractal baseline as a fraction of the region's width (Chang: 1/40); 0 = moss.colony_m in metres",
        0.0,
        1.0,
    ),
    p(
        "moss.colony_m",
        "",
        "A colony's typical radius, metres, through the scene's scale (used when moss.baseline is 0)",
        0.001,
        10.0,
    ),
    p(
        "moss.splash_m",
        "",
        "Height of the splash zone at the foot of a wall standing on the ground, metres: moss and algae grow there",
        0.0,
        10.0,
    ),
    p(
        "moss.ledge_top_m",
        "",
        "Depth of the wet band on top of each ledge (sill, coping, cornice), metres",
        0.0,
        2.0,
    ),
    p(
        "moss.open_wall",
        "",
        "How much moss the open wall takes, against 1 in the splash zone, on ledge tops, in joints and in rain shelter",
        0.0,
        1.0,
    ),
    p(
        "moss.mixed_species",
        "",
        "Mix grey-green lichen, dark moss and orange Caloplaca with moss.color",
        0.0,
        0.0,
    ),
    p(
        "moss.iterations",
        "",
        "Iterations of the mountain-shaped generator; each arm of a colony has 4^n + 1 dots",
        1.0,
        6.0,
    ),
    p(
        "moss.peak",
        "",
        "Height of the generator's peak as a fraction of its base; higher = rounder, denser colonies",
        0.0,
        1.0,
    ),
    p(
        "moss.dot_size",
        "",
        "Radius of one moss dot as a fraction of the baseline (at least half a pixel)",
        0.0,
        0.5,
    ),
    p(
        "moss.seed_rate",
        "",
        "Candidate sites tested with eq. 18 per baseline^2 of wall per year; more = more new colonies",
        0.0,
        100.0,
    ),
    p(
        "moss.spread",
        "",
        "Chance per colony per year of seeding a neighbour, so colonies cluster where the wall suits them",
        0.0,
        1.0,
    ),
    p(
        "moss.spread_distance",
        "",
        "Typical distance from a colony to the neighbour it seeds, in baselines",
        0.0,
        20.0,
    ),
    p(
        "moss.size_spread",
        "",
        "Spread of colony sizes (log-normal sigma); 0 = all colonies the same size",
        0.0,
        3.0,
    ),
    p(
        "moss.maturity",
        "",
        "Years a colony takes to reach its full size and number of arms",
        0.0,
        100.0,
    ),
];

/// Looks up a parameter's spec by dotted path.
pub fn param(path: &str) -> Option<&'static ParamSpec> {
    super::PARAMS.iter().find(|s| s.path == path)
}
