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
}

const fn p(path: &'static str, symbol: &'static str, doc: &'static str, min: f64, max: f64) -> ParamSpec {
    ParamSpec {
        path,
        symbol,
        doc,
        min,
        max,
    }
}

/// Every numeric parameter. Validation, `grime preset default` comments and
/// the GUI's sliders all read this table.
pub const PARAMS: &[ParamSpec] = &[
    p("seed", "", "Master random seed; the same seed gives byte-identical output", 0.0, u64::MAX as f64),
    p("sim.max_side", "", "Longest side of the simulation grid in pixels (0 = photo resolution); the streak pattern is computed on this grid and its stains are upsampled smoothly", 0.0, 16384.0),
    p("rain.layers", "", "Number of rainfalls; each one is a layer (Chang sec. 3.2)", 0.0, 200.0),
    p("rain.droplets", "n", "Droplets per rainfall on a wall reference_width grid pixels wide (Chang Table 1: 600)", 0.0, 100000.0),
    p("rain.reference_width", "", "Wall width that `droplets` refers to; the count scales with the region's width. 0 = no scaling", 0.0, 100000.0),
    p("rain.mass_max", "m", "First-layer droplet mass is uniform in 0..mass_max (Chang Table 1: 0..120)", 0.001, 10000.0),
    p("rain.mass_min", "", "A droplet lighter than this is removed and leaves its dirt behind", 0.0, 1000.0),
    p("rain.sigma", "sigma", "Spread of droplet mass and start position from one rainfall to the next (eqs. 16-17)", 0.0, 1000.0),
    p("rain.k_a", "k_a", "Wall absorption rate: how fast the wall soaks up a droplet's water (eqs. 5-6)", 0.0, 1.0),
    p("rain.k_s", "k_S", "Dirt deposition rate; the dissolution rate is k_D = 1 - k_S (eqs. 7-8)", 0.0, 1.0),
    p("rain.saturation", "a", "Water one grid pixel can hold; lower = longer streaks", 0.001, 1000.0),
    p("rain.i_sun", "I_sun", "Evaporation of wall water per diffusion round, over the whole wall (eq. 6)", 0.0, 1000.0),
    p("rain.r", "r", "Wall roughness chosen by the user; larger = more sideways scatter (eqs. 2-4)", 0.0, 1000.0),
    p("rain.r_max", "r_max", "Largest roughness; the braking terms divide by r_max - r + 1", 0.0, 1000.0),
    p("rain.b", "b", "Scatter constant of the sideways velocity b*r*xi*M_y (eq. 2)", 0.0, 1.0),
    p("rain.g", "g", "Gravity in grid pixels per step squared (eq. 4)", 0.0, 10.0),
    p("rain.rho", "rho", "Wall resistance: how much vertical roughness brakes the fall (eq. 4)", 0.0, 1000.0),
    p("rain.v_max", "", "Speed limit in grid pixels per step; at most 1 keeps streaks gap-free", 0.01, 1.0),
    p("rain.dt", "dt", "Time a droplet spends per step in the water and dirt exchange (eqs. 5-8); larger = shorter, darker streaks", 0.0001, 10.0),
    p("rain.max_steps", "", "Safety cap on the steps of one droplet", 1.0, 10_000_000.0),
    p("rain.initial_dirt", "I_D0", "Fresh grime per rainfall: smooth noise in 0..initial_dirt (Chang Table 1: 0..5)", 0.0, 1000.0),
    p("rain.initial_dirt_scale", "", "Feature size of the fresh-grime noise, grid pixels", 1.0, 4096.0),
    p("rain.ledge_dirt", "S_0", "Dirt a droplet washes off its ledge before it runs down the wall", 0.0, 1000.0),
    p("rain.delta", "delta", "Carry-over of dirt from one rainfall into the next (eqs. 13-14)", 0.0, 1.0),
    p("rain.eps", "eps", "How much deposited dirt raises the surface for the next rain, fraction of full scale (eq. 15)", 0.0, 1.0),
    p("rain.tau", "tau", "Moisture diffusion rate to each of 8 neighbours; at most 1/8 keeps water non-negative (eqs. 9-10)", 0.0, 0.125),
    p("rain.diffusion_rounds", "", "Diffusion rounds per rainfall, spread evenly over its droplets", 0.0, 1000.0),
    p("rain.diffusion_iterations", "", "Relaxation iterations of eqs. 9-10 per round", 0.0, 1000.0),
    p("rain.dirt_coupling", "", "How strongly dirt follows diffusing water (0 = dirt stays put, 1 = moves like water)", 0.0, 1.0),
    p("stain.color", "", "Colour of the rain dirt (sRGB), multiplied onto the wall", 0.0, 255.0),
    p("stain.opacity", "", "Opacity of each rain layer", 0.0, 1.0),
    p("stain.strength", "", "Stain alpha = strength * D / D_max", 0.0, 10.0),
    p("stain.percentile", "D_max", "Percentile of the first rainfall's deposits taken as D_max, so one hot pixel cannot wash out the rest", 0.5, 1.0),
    p("stain.softness", "", "Blur radius of stain edges, grid pixels", 0.0, 64.0),
];

/// Looks up a parameter's spec by dotted path.
pub fn param(path: &str) -> Option<&'static ParamSpec> {
    PARAMS.iter().find(|s| s.path == path)
}
