"""Cycles set up as the references here were rendered (the settings are
listed in cycles_fog_room.py's docstring): unbiased CPU path tracing, and
the World's homogeneous fog. Used by cycles_fog_room.py and by the
Blender add-on's tests (blender/tests)."""

import bpy


def set_present(owner, **values):
    """Sets each of `values` that `owner` has: Cycles 4.5 and 5.0 differ
    (5.0 has no `feature_set`, and finds homogeneous volumes itself)."""
    for name, value in values.items():
        if hasattr(owner, name):
            setattr(owner, name, value)


def unbiased(sc, spp, bounces, threads):
    """Cycles on the CPU with `spp` samples a pass, `bounces` for every
    kind of bounce (0: direct light and single scattering), `threads`
    threads: no denoising, adaptive sampling, clamping, light threshold,
    light tree or guiding; box pixel filter; Standard view."""
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    set_present(cy, feature_set="SUPPORTED")
    cy.shading_system = False
    cy.samples = spp
    cy.use_animated_seed = False
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.time_limit = 0.0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.use_light_tree = False
    cy.use_guiding = False
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.blur_glossy = 0.0
    cy.pixel_filter_type = "BOX"
    cy.film_exposure = 1.0
    for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                 "volume_bounces"):
        setattr(cy, attr, bounces)
    cy.transparent_max_bounces = 1024
    cy.min_light_bounces = 0
    cy.min_transparent_bounces = 0
    cy.use_auto_tile = False
    sc.render.threads_mode = "FIXED"
    sc.render.threads = threads
    sc.render.film_transparent = False
    sc.render.use_compositing = False
    sc.render.use_sequencer = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_layers[0].cycles.use_denoising = False


def world_fog(sc, density, albedo, g):
    """A black World (not sampled as a light) whose volume, where
    `density` > 0, is Volume Scatter (colour `albedo`, density `density`,
    Henyey–Greenstein `g`) + Volume Absorption (colour `albedo`, density
    `density`): σs = albedo·density, σa = (1 − albedo)·density, the
    homogeneous fog of Tyndall's `--density D --albedo A --g G`."""
    world = bpy.data.worlds.new("world")
    sc.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    nodes["Background"].inputs["Strength"].default_value = 0.0
    world.cycles.sampling_method = "NONE"
    if density > 0:
        a, d = albedo, density
        scatter = nodes.new("ShaderNodeVolumeScatter")
        scatter.inputs["Color"].default_value = (a, a, a, 1.0)
        scatter.inputs["Density"].default_value = d
        scatter.inputs["Anisotropy"].default_value = g
        if "phase" in scatter.bl_rna.properties:
            scatter.phase = "HENYEY_GREENSTEIN"
        absorb = nodes.new("ShaderNodeVolumeAbsorption")
        absorb.inputs["Color"].default_value = (a, a, a, 1.0)
        absorb.inputs["Density"].default_value = d
        add = nodes.new("ShaderNodeAddShader")
        links.new(scatter.outputs[0], add.inputs[0])
        links.new(absorb.outputs[0], add.inputs[1])
        links.new(add.outputs[0], nodes["World Output"].inputs["Volume"])
        world.cycles.volume_sampling = "MULTIPLE_IMPORTANCE"
        set_present(world.cycles, homogeneous_volume=True)
    return world
