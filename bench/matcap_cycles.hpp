#pragma once
// Blender Cycles rendering a sphere under an environment, for bench/matcap_bench (docs/matcap.md,
// "Next to Blender Cycles"). Blender is not a dependency: renderWithCycles returns nullopt, with a
// message, when no `blender` is on the PATH.
#include <brdfbake/brdf/material.hpp>
#include <brdfbake/maps/image.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace brdfbake {

// Cycles' Principled BSDF (Blender 3.4) with metallic 1, specular 0.5 and the single-scattering GGX
// distribution, written out from its source (intern/cycles/kernel/closure/bsdf_microfacet.h and
// svm_closure.h): f = D(h) G1(v) G1(l) F(l.h) / (4 (n.l)(n.v)), D GGX of alpha = roughness^2,
// separable Smith G (Walter et al. 2007 Eq. 34) and Cycles' Fresnel interpolation
// F = c + (1 - c) (F_d(l.h, 1.5) - 0.04) / 0.96, c the base colour, F_d the dielectric Fresnel of
// index 1.5 (Heidrich 2000 Eq. 13). Not Schlick's F = c + (1 - c)(1 - l.h)^5.
std::shared_ptr<const Material> cyclesPrincipledMetal(const Rgb& baseColor, double alpha);

struct CyclesRender {
  Image image;               // resolution^2 float RGBA, linear, row 0 at the top; alpha 0 off the sphere
  double seconds = 0.0;      // Blender's render call, without start-up and loading
  double wallSeconds = 0.0;  // the whole blender process
};

// Renders a unit sphere (a one-point point cloud: an exact sphere) with Principled metallic of
// `baseColor` and Cycles roughness sqrt(alpha), under the lat-long `environment` (an EXR in
// brdfbake's frame, mapped to Blender's: brdfbake (x, y, z) is Blender (-z, -x, y)), seen by an
// orthographic camera on +z (Blender -X) with up +y (Blender +Z) spanning [-1, 1]^2, box pixel filter
// of one pixel, `samples` samples per pixel, no denoising, no adaptive sampling, no clamping, the
// environment's texels read as they are (closest), Standard view transform. The files go to `work`.
std::optional<CyclesRender> renderWithCycles(const std::filesystem::path& environment, const Rgb& baseColor,
                                             double alpha, int resolution, int samples, int threads,
                                             const std::filesystem::path& work, std::string& message);

}  // namespace brdfbake
