// Test-only (tests/maps/test_texture_readers.cpp): reads a KTX2 file with ktx-parse, a reader
// brdfbake does not share, and prints as JSON what the test checks: the header, the data format
// descriptor, the key/value data, where each level lies, and, for a cube map, the texel a Vulkan
// cube sampler (nearest) reads at each direction of argv[3] (a JSON array of [x, y, z]) in every level.
//   node inspect_ktx2.mjs FILE '[[1,0,0],[0,1,0]]'
import { read } from 'ktx-parse';
import { readFileSync } from 'node:fs';
import { bytesPerTexel, cubeTexel, texel } from './cube_lookup.mjs';

const [file, directionsText] = process.argv.slice(2);
const bytes = new Uint8Array(readFileSync(file));
const container = read(bytes);
const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
const index = { dfdByteOffset: view.getUint32(48, true), dfdByteLength: view.getUint32(52, true),
                kvdByteOffset: view.getUint32(56, true), kvdByteLength: view.getUint32(60, true) };
const keyValue = {};
const keys = Object.keys(container.keyValue);
for (const key of keys) {
  const value = container.keyValue[key];
  keyValue[key] = typeof value === 'string' ? value : new TextDecoder().decode(value).replace(/\0+$/, '');
}
const levels = container.levels.map((level, k) => ({
  byteOffset: level.levelData.byteOffset - bytes.byteOffset,
  byteLength: level.levelData.byteLength,
  uncompressedByteLength: level.uncompressedByteLength,
}));
const lookups = [];
if (directionsText && container.faceCount === 6) {
  const directions = JSON.parse(directionsText);
  const texelBytes = bytesPerTexel[container.vkFormat];
  container.levels.forEach((level, k) => {
    const size = Math.max(1, container.pixelWidth >> k);
    const faceBytes = size * size * texelBytes;
    const start = level.levelData.byteOffset;
    lookups.push(directions.map((d) => {
      const { face, i, j } = cubeTexel(d, size);
      return texel(new DataView(bytes.buffer), start + face * faceBytes + (j * size + i) * texelBytes, container.vkFormat);
    }));
  });
}
const dfd = container.dataFormatDescriptor[0];
console.log(JSON.stringify({
  vkFormat: container.vkFormat, typeSize: container.typeSize, pixelWidth: container.pixelWidth,
  pixelHeight: container.pixelHeight, pixelDepth: container.pixelDepth, layerCount: container.layerCount,
  faceCount: container.faceCount, levelCount: container.levels.length,
  supercompressionScheme: container.supercompressionScheme, index, keys, keyValue, levels, lookups,
  dfd: { vendorId: dfd.vendorId, descriptorType: dfd.descriptorType, versionNumber: dfd.versionNumber,
         colorModel: dfd.colorModel, colorPrimaries: dfd.colorPrimaries, transferFunction: dfd.transferFunction,
         flags: dfd.flags, texelBlockDimension: dfd.texelBlockDimension, bytesPlane: dfd.bytesPlane,
         samples: dfd.samples.map((s) => ({ bitOffset: s.bitOffset, bitLength: s.bitLength,
                                             channelType: s.channelType, sampleLower: s.sampleLower >>> 0,
                                             sampleUpper: s.sampleUpper >>> 0 })) },
}));
