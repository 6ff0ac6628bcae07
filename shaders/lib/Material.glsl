// The drawn material (gpu/src/engine/SceneGeometry.cpp sets these per draw range): base-colour texture
// and the glTF alpha test (MASK; BLEND tested as MASK at 0.5).
#ifndef PENUMBRA_MATERIAL_GLSL
#define PENUMBRA_MATERIAL_GLSL

layout(binding = TEXUNIT_MATERIAL) uniform sampler2D tMaterial;
// x: alpha cutoff (< 0: not alpha-tested), y: base alpha (baseColorFactor.a), z: 1 if textured.
layout(location = UNIFORM_MATERIAL) uniform vec4 uMaterial;
// KHR_texture_transform of the base-colour texture (identity without it).
layout(location = UNIFORM_MATERIAL_UV) uniform mat3 uMaterialUv;

// The base-colour texture at texcoord uv (white without one); rgb linear.
vec4 materialTexel(vec2 uv) {
    if (uMaterial.z == 0.0) return vec4(1.0);
    return texture(tMaterial, (uMaterialUv * vec3(uv, 1.0)).xy);
}

// Whether the alpha test removes this fragment (texel alpha times the base alpha below cutoff).
bool materialCutOut(vec4 texel) {
    return uMaterial.x >= 0.0 && texel.a * uMaterial.y < uMaterial.x;
}

#endif
