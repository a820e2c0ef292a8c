#include "matcap_cycles.hpp"

#include <brdfbake/brdf/cook_torrance.hpp>
#include <brdfbake/brdf/fresnel.hpp>
#include <brdfbake/brdf/smith.hpp>
#include <brdfbake/core/progress.hpp>
#include <brdfbake/io/image_io.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

namespace brdfbake {
namespace {

class CyclesPrincipledMetal final : public Material {
 public:
  CyclesPrincipledMetal(const Rgb& baseColor, double alpha) : color_(baseColor), alpha_(alpha) {}
  std::string_view model() const override { return "cycles_principled_metal"; }
  bool viewIndependent() const override { return false; }
  Rgb shade(const ShadingGeometry& g, const Vec3& l) const override {
    const double nl = g.normal.dot(l), nv = g.normal.dot(g.view);
    if (!(nl > 0.0) || !(nv > 0.0)) return Rgb::Zero();
    const Vec3 h = (l + g.view).normalized();
    const double lh = l.dot(h), nh = g.normal.dot(h);
    if (!(lh > 0.0) || !(nh > 0.0)) return Rgb::Zero();
    const double f0 = fresnelDielectric(1.0, 1.5);
    const double fh = (fresnelDielectric(lh, 1.5) - f0) / (1.0 - f0);
    const Rgb f = color_ * (1.0 - fh) + fh;
    const double g2 = smithG1(nv, alpha_, true) * smithG1(nl, alpha_, true);
    return f * (ggxD(nh, alpha_) * g2 / (4.0 * nv));  // f_r (n.l)
  }
  std::optional<std::vector<ReflectionLobe>> reflectionLobes(const ShadingGeometry& g) const override {
    return std::vector<ReflectionLobe>{{ReflectionLobeShape::Ggx, g.normal, alpha_, 1.0}};
  }

 private:
  Rgb color_;
  double alpha_;
};

// The Blender script: scene, camera, world, material, render settings, render, save.
std::string script(const std::filesystem::path& environment, const Rgb& color, double alpha, int resolution,
                   int samples, int threads, const std::filesystem::path& output) {
  std::ostringstream s;
  s.precision(17);
  s << R"(import bpy, math, time
scene = bpy.context.scene
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o, do_unlink=True)
scene.render.engine = 'CYCLES'
scene.cycles.device = 'CPU'
scene.cycles.samples = )"
    << samples << R"(
scene.cycles.use_adaptive_sampling = False
scene.cycles.use_denoising = False
scene.cycles.pixel_filter_type = 'BOX'
scene.cycles.filter_width = 1.0
scene.cycles.max_bounces = 1
scene.cycles.glossy_bounces = 1
scene.cycles.diffuse_bounces = 0
scene.cycles.transmission_bounces = 0
scene.cycles.sample_clamp_direct = 0.0
scene.cycles.sample_clamp_indirect = 0.0
scene.cycles.blur_glossy = 0.0
scene.cycles.seed = 1
scene.render.threads_mode = 'FIXED'
scene.render.threads = )"
    << threads << R"(
scene.render.resolution_x = )"
    << resolution << R"(
scene.render.resolution_y = )"
    << resolution << R"(
scene.render.resolution_percentage = 100
scene.render.film_transparent = True
scene.view_settings.view_transform = 'Standard'
scene.view_settings.look = 'None'
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0
scene.render.image_settings.file_format = 'OPEN_EXR'
scene.render.image_settings.color_depth = '32'
scene.render.image_settings.color_mode = 'RGBA'
# brdfbake (x, y, z) is Blender (-z, -x, y) (Blender's equirectangular centre looks along +X, brdfbake's
# along -z): the camera on brdfbake +z is on Blender -X, looking along +X, up +Z.
camera_data = bpy.data.cameras.new('camera')
camera_data.type = 'ORTHO'
camera_data.ortho_scale = 2.0
camera_data.clip_start = 0.1
camera_data.clip_end = 100.0
camera = bpy.data.objects.new('camera', camera_data)
camera.location = (-10.0, 0.0, 0.0)
camera.rotation_euler = (math.pi / 2, 0.0, -math.pi / 2)
scene.collection.objects.link(camera)
scene.camera = camera
world = bpy.data.worlds.new('world')
world.use_nodes = True
nodes = world.node_tree.nodes
texture = nodes.new('ShaderNodeTexEnvironment')
texture.image = bpy.data.images.load(')"
    << environment.string() << R"(')
texture.interpolation = 'Closest'
texture.projection = 'EQUIRECTANGULAR'
world.node_tree.links.new(texture.outputs['Color'], nodes['Background'].inputs['Color'])
nodes['Background'].inputs['Strength'].default_value = 1.0
scene.world = world
material = bpy.data.materials.new('metal')
material.use_nodes = True
bsdf = material.node_tree.nodes['Principled BSDF']
bsdf.distribution = 'GGX'
bsdf.inputs['Base Color'].default_value = ()"
    << color[0] << ", " << color[1] << ", " << color[2] << R"(, 1.0)
bsdf.inputs['Metallic'].default_value = 1.0
bsdf.inputs['Specular'].default_value = 0.5
bsdf.inputs['Roughness'].default_value = )"
    << std::sqrt(alpha) << R"(
# One point of radius 1: Cycles renders a point cloud's points as exact spheres.
mesh = bpy.data.meshes.new('carrier')
carrier = bpy.data.objects.new('sphere', mesh)
scene.collection.objects.link(carrier)
group = bpy.data.node_groups.new('sphere', 'GeometryNodeTree')
group.outputs.new('NodeSocketGeometry', 'Geometry')
output = group.nodes.new('NodeGroupOutput')
points = group.nodes.new('GeometryNodePoints')
points.inputs['Count'].default_value = 1
points.inputs['Radius'].default_value = 1.0
set_material = group.nodes.new('GeometryNodeSetMaterial')
set_material.inputs['Material'].default_value = material
group.links.new(points.outputs['Geometry'], set_material.inputs['Geometry'])
group.links.new(set_material.outputs['Geometry'], output.inputs[0])
modifier = carrier.modifiers.new('sphere', 'NODES')
modifier.node_group = group
scene.render.filepath = ')"
    << output.string() << R"('
start = time.time()
bpy.ops.render.render(write_still=True)
print('BRDFBAKE_RENDER_SECONDS', time.time() - start)
)";
  return s.str();
}

}  // namespace

std::shared_ptr<const Material> cyclesPrincipledMetal(const Rgb& baseColor, double alpha) {
  return std::make_shared<CyclesPrincipledMetal>(baseColor, alpha);
}

std::optional<CyclesRender> renderWithCycles(const std::filesystem::path& environment, const Rgb& baseColor,
                                             double alpha, int resolution, int samples, int threads,
                                             const std::filesystem::path& work, std::string& message) {
  if (std::system("command -v blender > /dev/null 2>&1") != 0) {
    message = "blender is not installed (Debian: apt-get install blender); the Cycles comparison is skipped";
    return std::nullopt;
  }
  std::filesystem::create_directories(work);
  const auto output = work / ("cycles_" + std::to_string(samples) + ".exr");
  const auto scriptPath = work / "render.py";
  std::ofstream(scriptPath) << script(std::filesystem::absolute(environment), baseColor, alpha, resolution, samples,
                                      threads, std::filesystem::absolute(output));
  const std::string command = "blender -b --factory-startup -noaudio -P '" + scriptPath.string() + "' 2>&1";
  const auto start = std::chrono::steady_clock::now();
  FILE* pipe = popen(command.c_str(), "r");
  std::string log;
  char buffer[4096];
  while (pipe && std::fgets(buffer, sizeof buffer, pipe)) log += buffer;
  const int status = pipe ? pclose(pipe) : -1;
  CyclesRender render;
  render.wallSeconds = secondsSince(start);
  std::smatch match;
  if (status != 0 || !std::regex_search(log, match, std::regex("BRDFBAKE_RENDER_SECONDS ([0-9.eE+-]+)"))) {
    message = "blender failed (status " + std::to_string(status) + "):\n" +
              log.substr(log.size() > 3000 ? log.size() - 3000 : 0);
    return std::nullopt;
  }
  render.seconds = std::stod(match[1]);
  render.image = readImage(output);
  return render;
}

}  // namespace brdfbake
