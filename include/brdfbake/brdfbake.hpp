#pragma once
/// @file
/// Every public header of brdfbake in one include. Parts that were not built or installed (a
/// bake-only package has no env, output, measured, fit, spec or run) are skipped.

// core
#if __has_include(<brdfbake/core/error.hpp>)
#include <brdfbake/core/color.hpp>
#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>
#include <brdfbake/core/math.hpp>
#include <brdfbake/core/memory_budget.hpp>
#include <brdfbake/core/named_values.hpp>
#include <brdfbake/core/printable.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/core/text_numbers.hpp>
#include <brdfbake/core/version.hpp>
#endif

// brdf
#if __has_include(<brdfbake/brdf/blinn_conversion.hpp>)
#include <brdfbake/brdf/blinn_conversion.hpp>
#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/brdf/half_difference_table.hpp>
#include <brdfbake/brdf/lobes.hpp>
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/brdf/npr.hpp>
#include <brdfbake/brdf/phong.hpp>
#include <brdfbake/brdf/reflection_lobe.hpp>
#include <brdfbake/brdf/smith.hpp>
#include <brdfbake/brdf/spectrum.hpp>
#include <brdfbake/brdf/split_sum.hpp>
#endif

// maps
#if __has_include(<brdfbake/maps/cube_map.hpp>)
#include <brdfbake/maps/cube_map.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/map_mips.hpp>
#include <brdfbake/maps/paraboloid_map.hpp>
#include <brdfbake/maps/parameterization.hpp>
#include <brdfbake/maps/radial_table.hpp>
#include <brdfbake/maps/sh.hpp>
#include <brdfbake/maps/sphere_map.hpp>
#include <brdfbake/maps/texel_format.hpp>
#endif

// io
#if __has_include(<brdfbake/io/files.hpp>)
#include <brdfbake/io/files.hpp>
#include <brdfbake/io/image_io.hpp>
#include <brdfbake/io/json_reader.hpp>
#include <brdfbake/io/json_text.hpp>
#include <brdfbake/io/map_file.hpp>
#include <brdfbake/io/text_io.hpp>
#include <brdfbake/io/texture.hpp>
#endif

// bake
#if __has_include(<brdfbake/bake/accuracy.hpp>)
#include <brdfbake/bake/accuracy.hpp>
#include <brdfbake/bake/auto_config.hpp>
#include <brdfbake/bake/baked_mips.hpp>
#include <brdfbake/bake/baker.hpp>
#include <brdfbake/bake/interpolation_error.hpp>
#include <brdfbake/bake/map_function.hpp>
#include <brdfbake/bake/radial_profile.hpp>
#endif

// env
#if __has_include(<brdfbake/env/env_accuracy.hpp>)
#include <brdfbake/env/camera.hpp>
#include <brdfbake/env/dfg_table.hpp>
#include <brdfbake/env/env_accuracy.hpp>
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/material_under_environment.hpp>
#include <brdfbake/env/prefilter.hpp>
#include <brdfbake/env/prefilter_lobe.hpp>
#include <brdfbake/env/prefilter_stack.hpp>
#include <brdfbake/env/sh_irradiance.hpp>
#endif

// output
#if __has_include(<brdfbake/output/baked_output.hpp>)
#include <brdfbake/output/baked_output.hpp>
#include <brdfbake/output/preview.hpp>
#endif

// measured
#if __has_include(<brdfbake/measured/measured_io.hpp>)
#include <brdfbake/measured/measured_io.hpp>
#include <brdfbake/measured/measured_table.hpp>
#endif

// fit
#if __has_include(<brdfbake/fit/cornell_grid.hpp>)
#include <brdfbake/fit/cornell_grid.hpp>
#include <brdfbake/fit/fit_file.hpp>
#include <brdfbake/fit/held_out.hpp>
#include <brdfbake/fit/lobe_fit.hpp>
#include <brdfbake/fit/mirror_direction.hpp>
#include <brdfbake/fit/table_interpolation.hpp>
#endif

// spec
#if __has_include(<brdfbake/spec/brdf_file.hpp>)
#include <brdfbake/spec/brdf_file.hpp>
#include <brdfbake/spec/material_file.hpp>
#include <brdfbake/spec/material_spec.hpp>
#include <brdfbake/spec/spec.hpp>
#endif

// run
#if __has_include(<brdfbake/run/chart.hpp>)
#include <brdfbake/run/chart.hpp>
#include <brdfbake/run/convert_output.hpp>
#include <brdfbake/run/describe_output.hpp>
#include <brdfbake/run/evaluate.hpp>
#include <brdfbake/run/fit_report.hpp>
#include <brdfbake/run/fit_table.hpp>
#include <brdfbake/run/gnuplot.hpp>
#include <brdfbake/run/ibl_job.hpp>
#include <brdfbake/run/interpolation_chart.hpp>
#include <brdfbake/run/job.hpp>
#include <brdfbake/run/map_outputs.hpp>
#include <brdfbake/run/matcap_job.hpp>
#include <brdfbake/run/prefilter_job.hpp>
#include <brdfbake/run/preview_job.hpp>
#include <brdfbake/run/sample_output.hpp>
#include <brdfbake/run/spec_runner.hpp>
#endif
