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
    }
}

/// Every numeric parameter. Validation, `grime preset default` comments and
/// the GUI's sliders all read this table. Entries with `min == max` document
/// a switch, a name or a list (never range-checked).
pub const PARAMS: &[ParamSpec] = &ALL;

/// The tables of the preset's modules, in section order.
const PARTS: &[&[ParamSpec]] = &[
    CORE,
    super::imperfections::ROWS[0],
    super::imperfections::ROWS[1],
    super::imperfections::ROWS[2],
    super::imperfections::ROWS[3],
    super::imperfections::ROWS[4],
    super::imperfections::ROWS[5],
    super::weathering::ROWS[0],
    super::weathering::ROWS[1],
    super::weathering::ROWS[2],
    super::weathering::ROWS[3],
    super::weathering::ROWS[4],
];

const ALL: [ParamSpec; rows(PARTS)] = join(PARTS);

const fn rows(parts: &[&[ParamSpec]]) -> usize {
    let (mut i, mut n) = (0, 0);
    while i < parts.len() {
        n += parts[i].len();
        i += 1;
    }
    n
}

/// The parts one after another (a `const` concatenation).
const fn join<const N: usize>(parts: &[&[ParamSpec]]) -> [ParamSpec; N] {
    let mut out = [p("", "", "", 0.0, 0.0); N];
    let (mut i, mut k) = (0, 0);
    while i < parts.len() {
        let mut j = 0;
        while j < parts[i].len() {
            out[k] = parts[i][j];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    out
}

/// The core effects' parameters.
const CORE: &[ParamSpec] = &[
    p(
        "seed",
        "",
        "Master random seed; the same seed gives byte-identical output",
        0.0,
        i64::MAX as f64,
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
        "Blur radius of stain edges, grid pixels",
        0.0,
        64.0,
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
    ),
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
        "Length of a colony's fractal baseline as a fraction of the region's width (Chang: 1/40)",
        0.001,
        1.0,
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
    p(
        "dust.enabled",
        "",
        "Let dust settle (\"dust film\" and \"dust granules\" layers above the moss)",
        0.0,
        0.0,
    ),
    p(
        "dust.days",
        "t",
        "Days of dust accumulation; later days add particles to earlier ones (Santos eq. 1)",
        0.0,
        36500.0,
    ),
    p(
        "dust.environment",
        "",
        "Accumulation rates measured by Santos: \"low-activity\", \"high-activity\", \"steep-start\", \"desktop\", or \"custom\" to use film_segments and mask_segments",
        0.0,
        0.0,
    ),
    p(
        "dust.film_segments",
        "",
        "Custom fine-particle rates (environment = \"custom\"): [{ days, alpha, beta }, ...], each eq. 1 in turn; the last runs on",
        0.0,
        0.0,
    ),
    p(
        "dust.mask_segments",
        "",
        "Custom coarse-element rates (environment = \"custom\"): [{ days, alpha, beta }, ...], each eq. 1 in turn; the last runs on",
        0.0,
        0.0,
    ),
    p(
        "dust.film_segments.days",
        "",
        "Days a custom film rate lasts (0 = until the end)",
        0.0,
        36500.0,
    ),
    p(
        "dust.film_segments.alpha",
        "alpha",
        "Fine particles per in^2 per day of a custom film rate (Santos eq. 1)",
        0.0,
        10000.0,
    ),
    p(
        "dust.film_segments.beta",
        "beta",
        "Extra fine particles per in^2 on the first day of a custom film rate (Santos eq. 1)",
        0.0,
        10000.0,
    ),
    p(
        "dust.mask_segments.days",
        "",
        "Days a custom granule rate lasts (0 = until the end)",
        0.0,
        36500.0,
    ),
    p(
        "dust.mask_segments.alpha",
        "alpha",
        "Coarse elements per in^2 per day of a custom granule rate (Santos eq. 1)",
        0.0,
        10000.0,
    ),
    p(
        "dust.mask_segments.beta",
        "beta",
        "Extra coarse elements per in^2 on the first day of a custom granule rate (Santos eq. 1)",
        0.0,
        10000.0,
    ),
    p(
        "dust.ppi",
        "",
        "Pixels per inch of the wall; the area A of eq. 1 is the region's pixels / ppi^2 (Santos: 150)",
        1.0,
        10000.0,
    ),
    p(
        "dust.film_greys",
        "c_i",
        "Grey levels of the three kinds of fine particle (Santos: 100, 150, 200)",
        0.0,
        255.0,
    ),
    p(
        "dust.film_weights",
        "w_i",
        "Opacity weight of each grey in the adjusted particle count ANP (Santos eq. 3)",
        0.0,
        100.0,
    ),
    p(
        "dust.anp_max",
        "ANP_max",
        "Weighted particle count at which a pixel's film is opaque (Santos eq. 4: 1.2)",
        0.001,
        1000.0,
    ),
    p(
        "dust.granule_color",
        "k",
        "Colour of coarse dust elements, sRGB (Santos eq. 7: 220, 220, 220)",
        0.0,
        255.0,
    ),
    p(
        "dust.granule_size",
        "w",
        "Largest width of a coarse element in pixels (Santos Table 1: 12 to 36)",
        1.0,
        1024.0,
    ),
    p(
        "dust.arc_share",
        "",
        "Share of arcs among coarse elements (Santos alg. 1)",
        0.0,
        1.0,
    ),
    p(
        "dust.clump_share",
        "",
        "Share of clumps among coarse elements (Santos alg. 2)",
        0.0,
        1.0,
    ),
    p(
        "dust.hair_share",
        "",
        "Share of hairs among coarse elements (Santos alg. 3)",
        0.0,
        1.0,
    ),
    p(
        "dust.theta_v",
        "theta_v",
        "Viewing angle from the wall's normal in degrees; 0 = head-on, where the film is invisible (Santos eq. 8)",
        0.0,
        90.0,
    ),
    p(
        "dust.theta_i",
        "theta_i",
        "Light incidence angle from the wall's normal in degrees; grazing light shows more dust (Santos eq. 9)",
        0.0,
        90.0,
    ),
    p(
        "dust.film_opacity",
        "",
        "Opacity of the dust film layer",
        0.0,
        1.0,
    ),
    p(
        "dust.granule_opacity",
        "",
        "Opacity of the dust granules layer",
        0.0,
        1.0,
    ),
    p(
        "gammaton.enabled",
        "",
        "Run the gamma-tons: particles carrying substances (rust, salt, dirt...) from sources over the wall, one layer per substance",
        0.0,
        0.0,
    ),
    p(
        "gammaton.particles",
        "",
        "Gamma-tons emitted per iteration, over all sources",
        0.0,
        20000000.0,
    ),
    p(
        "gammaton.iterations",
        "",
        "Iterations: emit and trace, then apply the ageing rules",
        0.0,
        100.0,
    ),
    p(
        "gammaton.max_depth",
        "",
        "Most contacts one gamma-ton makes before it settles (caps the tracing)",
        1.0,
        1000.0,
    ),
    p(
        "gammaton.radius",
        "r",
        "Interaction radius in grid pixels: the pixels a contact exchanges substance with (thesis eq. 3.19)",
        0.0,
        4.0,
    ),
    p(
        "gammaton.p_straight",
        "p_s",
        "Initial probability of a straight hop after a contact (Russian roulette, eq. 3.10)",
        0.0,
        1.0,
    ),
    p(
        "gammaton.p_parabolic",
        "p_p",
        "Initial probability of a parabolic bounce after a contact",
        0.0,
        1.0,
    ),
    p(
        "gammaton.p_flow",
        "p_f",
        "Initial probability of flowing down the wall after a contact; settling takes the rest (eq. 3.9)",
        0.0,
        1.0,
    ),
    p(
        "gammaton.d_straight",
        "Delta_s",
        "Deterioration of p_s per contact (eq. 3.21)",
        0.0,
        1.0,
    ),
    p(
        "gammaton.d_parabolic",
        "Delta_p",
        "Deterioration of p_p per contact (eq. 3.21)",
        0.0,
        1.0,
    ),
    p(
        "gammaton.d_flow",
        "Delta_f",
        "Deterioration of p_f per contact (eq. 3.21)",
        0.0,
        1.0,
    ),
    p(
        "gammaton.hop",
        "",
        "Length of a straight hop or a parabolic bounce, grid pixels",
        0.5,
        200.0,
    ),
    p(
        "gammaton.flow_step",
        "",
        "Length of one flow segment between contacts, grid pixels",
        0.5,
        50.0,
    ),
    p(
        "gammaton.wander",
        "",
        "Sideways wander of flowing gamma-tons; 0 = straight down the slope",
        0.0,
        2.0,
    ),
    p(
        "gammaton.consistent",
        "",
        "Consistent transport (exchange at every contact, eqs. 3.26-3.27) instead of classic (absorb at stops, deposit on settling, 3.23-3.25)",
        0.0,
        0.0,
    ),
    p(
        "gammaton.sources",
        "",
        "Sources: [{ kind = \"sky\" | \"ground\" | \"line\", share, points = [[x, y], ...] (photo pixels, line only), carries = [amount per substance] }]",
        0.0,
        0.0,
    ),
    p(
        "gammaton.sources.share",
        "",
        "A source's share of the particles (shares are normalised)",
        0.0,
        1000.0,
    ),
    p(
        "gammaton.sources.spots",
        "",
        "Line sources: emit from this many fixed spots along the line (fixings, brackets); 0 = anywhere along it",
        0.0,
        10000.0,
    ),
    p(
        "gammaton.sources.carries",
        "s_i",
        "What each gamma-ton of this source starts with, one amount per substance in order",
        0.0,
        1000.0,
    ),
    p(
        "gammaton.substances.stops.value",
        "",
        "A blend stop's concentration, 0..1 of the substance's scale",
        0.0,
        1.0,
    ),
    p(
        "gammaton.substances.stops.color",
        "",
        "A blend stop's colour, sRGB [r, g, b]",
        0.0,
        255.0,
    ),
    p(
        "gammaton.substances.stops.opacity",
        "",
        "A blend stop's opacity",
        0.0,
        1.0,
    ),
    p(
        "gammaton.substances",
        "",
        "Substances (at most 4): [{ name, absorb, deposit, initial, scale, stops = [{ value, color, opacity }] }]",
        0.0,
        0.0,
    ),
    p(
        "gammaton.substances.absorb",
        "a",
        "Absorption rate of the gamma-tons for this substance (eqs. 3.23, 3.26)",
        -1.0,
        1.0,
    ),
    p(
        "gammaton.substances.deposit",
        "k",
        "Deposition rate of the wall for this substance (eqs. 3.25, 3.26)",
        0.0,
        4.0,
    ),
    p(
        "gammaton.substances.initial",
        "",
        "Concentration on the whole wall before the first iteration",
        0.0,
        1000.0,
    ),
    p(
        "gammaton.substances.scale",
        "",
        "Concentration above initial shown by the last blend stop (the layer shows what the gamma-tons gathered)",
        1e-06,
        1000000.0,
    ),
    p(
        "gammaton.rules",
        "",
        "Ageing rules after each iteration: [{ kind = \"transfer\" | \"deteriorate\", from, to, rate, only_where }] (eqs. 3.28-3.29)",
        0.0,
        0.0,
    ),
    p(
        "gammaton.rules.rate",
        "k",
        "Rate: transfer moves k c; deteriorate multiplies by 1 + k (evaporation: k < 0)",
        -1.0,
        1.0,
    ),
];

/// Looks up a parameter's spec by dotted path.
pub fn param(path: &str) -> Option<&'static ParamSpec> {
    PARAMS.iter().find(|s| s.path == path)
}
