// Shared by the inspectors: the cube map face selection of the Vulkan specification (section
// "Cube Map Face Selection and Transformations", the same table as OpenGL 4.6 section 8.13), typed
// from the specification, not from brdfbake: the major axis picks the face (layer 0..5 = +X, -X,
// +Y, -Y, +Z, -Z), then s = (sc / |rc| + 1) / 2, t = (tc / |rc| + 1) / 2, and texel (i, j) =
// (floor(s N), floor(t N)) counts j in memory order (row 0 first).
export function cubeTexel(direction, size) {
  const [rx, ry, rz] = direction;
  const ax = Math.abs(rx), ay = Math.abs(ry), az = Math.abs(rz);
  let face, sc, tc, rc;
  if (ax >= ay && ax >= az) {
    rc = ax;
    if (rx >= 0) { face = 0; sc = -rz; tc = -ry; } else { face = 1; sc = rz; tc = -ry; }
  } else if (ay >= az) {
    rc = ay;
    if (ry >= 0) { face = 2; sc = rx; tc = rz; } else { face = 3; sc = rx; tc = -rz; }
  } else {
    rc = az;
    if (rz >= 0) { face = 4; sc = rx; tc = -ry; } else { face = 5; sc = -rx; tc = -ry; }
  }
  const s = 0.5 * (sc / rc + 1), t = 0.5 * (tc / rc + 1);
  const clamp = (v) => Math.min(size - 1, Math.max(0, Math.floor(v * size)));
  return { face, i: clamp(s), j: clamp(t) };
}

// IEEE 754 binary16 to a number.
export function half(bits) {
  const sign = bits & 0x8000 ? -1 : 1, exponent = (bits >> 10) & 0x1f, mantissa = bits & 0x3ff;
  if (exponent === 0) return sign * mantissa * 2 ** -24;
  if (exponent === 31) return mantissa ? NaN : sign * Infinity;
  return sign * (1 + mantissa / 1024) * 2 ** (exponent - 15);
}

// Unsigned small floats (5-bit exponent, bias 15) and RGB9E5, from the Vulkan specification.
function smallFloat(bits, mantissaBits) {
  const exponent = bits >> mantissaBits, mantissa = bits & ((1 << mantissaBits) - 1);
  if (exponent === 0) return mantissa * 2 ** (-14 - mantissaBits);
  return (1 + mantissa / 2 ** mantissaBits) * 2 ** (exponent - 15);
}

// The RGBA of the texel at byte `offset` of `view` (a DataView), for a VkFormat.
export function texel(view, offset, vkFormat) {
  switch (vkFormat) {
    case 97: // R16G16B16A16_SFLOAT
      return [0, 1, 2, 3].map((c) => half(view.getUint16(offset + 2 * c, true)));
    case 109: // R32G32B32A32_SFLOAT
      return [0, 1, 2, 3].map((c) => view.getFloat32(offset + 4 * c, true));
    case 123: { // E5B9G9R9_UFLOAT_PACK32
      const w = view.getUint32(offset, true), scale = 2 ** ((w >>> 27) - 15 - 9);
      return [w & 511, (w >>> 9) & 511, (w >>> 18) & 511].map((m) => m * scale).concat([1]);
    }
    case 122: { // B10G11R11_UFLOAT_PACK32
      const w = view.getUint32(offset, true);
      return [smallFloat(w & 0x7ff, 6), smallFloat((w >>> 11) & 0x7ff, 6), smallFloat((w >>> 22) & 0x3ff, 5), 1];
    }
    default:
      throw new Error('format ' + vkFormat + ' not decoded by this test');
  }
}

export const bytesPerTexel = { 97: 8, 109: 16, 123: 4, 122: 4 };
