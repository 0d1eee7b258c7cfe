//! The validation and behaviour tests of granmix, one module per concern, linked into
//! one test binary (one link instead of one per file keeps the suite's build short).

mod added_mass;
mod bagnold_incline;
mod barrier_loads;
mod barrier_panels;
mod barrier_suction;
mod body_mean_force;
mod cohesive_cut;
mod contact_restitution;
mod determinism;
mod fmu_fmi_crate;
mod memory_budget;
mod perturbation;
mod saturated;
mod scene_errors;
mod scene_headers;
mod scenes_smoke;
mod sleep;
mod slope_stability;
mod soil_models;
mod spreading_density;
mod stability_guard;
mod thin_layer_slope;
mod validation_blocks;
mod validation_collapse_2d;
mod validation_collapse_3d;
mod validation_geostatic;
mod validation_incline;
mod validation_rings;
mod validation_srm;
mod water;
mod water_channel;
