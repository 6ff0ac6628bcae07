// Bounds on what a scene may hold, checked when it is loaded (geometry/scene/GltfLoader.h,
// geometry/scene/Scene.h) so that hostile or mistaken input gets a clear InputError up front instead of
// an abort inside a library, an allocation failure or minutes of work.
#pragma once

#include <cstddef>

namespace geometry {

// Largest |coordinate| of any world-space vertex, camera position or light point (centre, u, v).
// Everything downstream is single precision: at 1e7 the float spacing is already 1 unit, so a
// model with unit-sized features there is quantised beyond use. Products of up to four coordinates (plane equations at a point, squared lengths
// of edge cross products, Gram determinants of the light axes) stay below 1e28, far from float
// overflow (3.4e38), and far from Embree's own bound on ray origins and directions (|x| below
// 1.8e19, where its ray.valid() assertion aborts the process).
inline constexpr float kMaxCoordinate = 1e7f;

// Triangles one procedural object (sphere, torus of the scene JSON) may have: 2^21, a sphere of
// 1448 segments or a 1024 x 1024 torus, finer than any image it can be rendered to. Loading and
// preparing a scene costs about 3 us and 500 bytes per triangle (mesh, topology, GPU buffers;
// penumbra-render --method hard on a 1448-segment sphere: 6 s and 1.1 GB on llvmpipe), so this
// many is seconds and a gigabyte; 4096 segments (17M triangles) took 63 s and 8.4 GB.
inline constexpr std::size_t kMaxObjectTriangles = std::size_t(1) << 21;

// Triangles a whole scene may have (every object, glTF included): 2^22, about 2 GB and a dozen
// seconds of preparation by the figures above; the largest level shipped here has 67k.
inline constexpr std::size_t kMaxSceneTriangles = std::size_t(1) << 22;

// Largest side of a texture image: 16384, the GL_MAX_TEXTURE_SIZE every OpenGL 4.5
// implementation offers at least (the GPU side still checks its own limit when uploading).
// Checked from the PNG or JPEG header, before a pixel is decoded: a JPEG of a few hundred bytes
// can claim 65535 x 65535 pixels.
inline constexpr int kMaxTextureSide = 16384;

// Pixels all the textures of one glTF file may have together: 2^26 (64 Mpixels, 256 MiB as
// RGBA8, twice that while decoding), e.g. sixteen 2048 x 2048 textures; the textured levels
// shipped here have 2.3 Mpixels at most
// (kaos2).
inline constexpr std::size_t kMaxTexturePixels = std::size_t(1) << 26;

} // namespace geometry
