// The drawn material (gpu/src/engine/SceneGeometry.cpp sets these per draw range): base-colour texture
// and the glTF alpha test (MASK; BLEND tested as MASK at 0.5).
#ifndef PENUMBRA_MATERIAL_GLSL
#define PENUMBRA_MATERIAL_GLSL

layout(binding = TEXUNIT_MATERIAL) uniform sampler2D tMaterial;
// x: alpha cutoff (< 0: not alpha-tested), y: base alpha (baseColorFactor.a), z: 1 if textured.
layout(location = UNIFORM_MATERIAL) uniform vec4 uMaterial;
// KHR_texture_transform of the base-colour texture (identity without it).
layout(location = UNIFORM_MATERIAL_UV) uniform mat3 uMaterialUv;

// The base-colour texture at texcoord uv (white without one); rgb linear. MATERIAL_BASE_LEVEL:
// bilinear on the base level, as `raytrace` tests alpha (a shadow map of a whole tree would
// otherwise take a coarse mip level, whose averaged alpha widens or drops thin leaves).
vec4 materialTexel(vec2 uv) {
    if (uMaterial.z == 0.0) return vec4(1.0);
#ifdef MATERIAL_BASE_LEVEL
    return textureLod(tMaterial, (uMaterialUv * vec3(uv, 1.0)).xy, 0.0);
#else
    return texture(tMaterial, (uMaterialUv * vec3(uv, 1.0)).xy);
#endif
}

// Whether the alpha test removes this fragment (texel alpha times the base alpha below cutoff).
bool materialCutOut(vec4 texel) {
    return uMaterial.x >= 0.0 && texel.a * uMaterial.y < uMaterial.x;
}

#endif
