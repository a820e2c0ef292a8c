// Test-only (tests/maps/test_texture_readers.cpp): reads a DDS file's header with parse-dds, a
// reader brdfbake does not share, and prints as JSON its description (shape, format, cube map, the
// byte range of every image) and, for an RGBA32F cube map, the texel a Vulkan cube sampler (nearest)
// reads at each direction of argv[3] in every level, from the image ranges parse-dds gives.
import { createRequire } from 'node:module';
import { readFileSync } from 'node:fs';
import { cubeTexel, texel } from './cube_lookup.mjs';

const parseDds = createRequire(import.meta.url)('parse-dds');
const [file, directionsText] = process.argv.slice(2);
const buffer = readFileSync(file);
const arrayBuffer = buffer.buffer.slice(buffer.byteOffset, buffer.byteOffset + buffer.byteLength);
const dds = parseDds(arrayBuffer);
const lookups = [];
if (directionsText && dds.cubemap) {
  const directions = JSON.parse(directionsText);
  const levels = dds.images.length / 6;
  const view = new DataView(arrayBuffer);
  for (let k = 0; k < levels; ++k) {
    lookups.push(directions.map((d) => {
      const { face, i, j } = cubeTexel(d, Math.max(1, dds.shape[0] >> k));
      const image = dds.images[face * levels + k];  // parse-dds lists faces outer, levels inner
      return texel(view, image.offset + (j * image.shape[0] + i) * 16, 109);
    }));
  }
}
console.log(JSON.stringify({ shape: dds.shape, format: dds.format, cubemap: dds.cubemap, images: dds.images, lookups }));
