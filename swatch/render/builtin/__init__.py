"""The built-in engine (``--engine builtin``): the half-vector thin-film model rendered by table lookup.

Beside :mod:`swatch.render.mitsuba` (the path tracer), as pbrt-v4 keeps its back ends beside the shared
interfaces: the request, camera, scene, lighting, environment maps and image (:mod:`swatch.render`) are shared;
what only this engine does is here. :mod:`~swatch.render.builtin.shading` (the per-thickness colour table over
cos θ_d and the intensity factor of each model), :mod:`~swatch.render.builtin.pointlight` (one directional light:
:func:`~swatch.render.builtin.pointlight.render_pointlight`), :mod:`~swatch.render.builtin.env_shading` and
:mod:`~swatch.render.builtin.env_aniso` (the BRDF integrated over an environment, isotropic and brushed) and
:mod:`~swatch.render.builtin.env_render` (renders under an environment:
:func:`~swatch.render.builtin.env_render.render_swatch_environment`). Nothing is imported here: the dispatcher
(:mod:`swatch.render.dispatch`) imports the engine's entry points.
"""
