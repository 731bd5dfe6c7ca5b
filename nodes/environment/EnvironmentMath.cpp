#include <sgfx/nodes/environment/EnvironmentMath.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx::env {

namespace {
constexpr float kPi = 3.14159265358979f;

// Tangent frame around a unit normal (any orthonormal pair will do for an isotropic lobe).
void basis(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
    const glm::vec3 up = std::abs(n.z) < 0.999f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
    t = glm::normalize(glm::cross(up, n));
    b = glm::cross(n, t);
}

// GGX half vector for the Hammersley point xi, around +Z (Karis 2013, ImportanceSampleGGX).
glm::vec3 ggxHalfVector(glm::vec2 xi, float alpha) {
    const float a2 = alpha * alpha;
    const float phi = 2.0f * kPi * xi.x;
    const float cosTheta = std::sqrt((1.0f - xi.y) / (1.0f + (a2 - 1.0f) * xi.y));
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

// The shader's α: perceptual roughness clamped as brdf_metallic_roughness.glsl does, squared.
float alphaOf(float roughness) {
    const float r = std::max(roughness, 0.045f);
    return r * r;
}

float ggxD(float NdotH, float alpha) {
    const float a2 = alpha * alpha;
    const float d = NdotH * NdotH * (a2 - 1.0f) + 1.0f;
    return a2 / (kPi * d * d);
}

glm::vec3 bilinear(const CubeImage& c, int face, glm::vec2 st) {
    const float x = std::clamp(st.x * float(c.size) - 0.5f, 0.0f, float(c.size - 1));
    const float y = std::clamp(st.y * float(c.size) - 0.5f, 0.0f, float(c.size - 1));
    const int x0 = int(x), y0 = int(y);
    const int x1 = std::min(x0 + 1, c.size - 1), y1 = std::min(y0 + 1, c.size - 1);
    const float fx = x - float(x0), fy = y - float(y0);
    return glm::mix(glm::mix(c.texel(face, x0, y0), c.texel(face, x1, y0), fx),
                    glm::mix(c.texel(face, x0, y1), c.texel(face, x1, y1), fx), fy);
}
} // namespace

CubeImage CubeImage::filled(int size, glm::vec3 radiance) {
    CubeImage c;
    c.size = size;
    for (auto& f : c.faces)
        f.assign(std::size_t(size) * size, radiance);
    return c;
}

glm::vec3 CubeImage::sample(glm::vec3 direction) const {
    const CubeCoord cc = cubeCoord(direction);
    return bilinear(*this, cc.face, cc.st);
}

CubeImage CubeImage::downsampled() const {
    CubeImage d;
    d.size = size / 2;
    for (int f = 0; f < 6; ++f) {
        d.faces[std::size_t(f)].resize(std::size_t(d.size) * d.size);
        for (int t = 0; t < d.size; ++t)
            for (int s = 0; s < d.size; ++s)
                d.texel(f, s, t) = 0.25f * (texel(f, 2 * s, 2 * t) + texel(f, 2 * s + 1, 2 * t) +
                                            texel(f, 2 * s, 2 * t + 1) + texel(f, 2 * s + 1, 2 * t + 1));
    }
    return d;
}

CubeCoord cubeCoord(glm::vec3 d) {
    const glm::vec3 a = glm::abs(d);
    int face;
    float sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0.0f ? 0 : 1;
        sc = d.x >= 0.0f ? -d.z : d.z;
        tc = -d.y;
        ma = a.x;
    } else if (a.y >= a.z) {
        face = d.y >= 0.0f ? 2 : 3;
        sc = d.x;
        tc = d.y >= 0.0f ? d.z : -d.z;
        ma = a.y;
    } else {
        face = d.z >= 0.0f ? 4 : 5;
        sc = d.z >= 0.0f ? d.x : -d.x;
        tc = -d.y;
        ma = a.z;
    }
    return {face, glm::vec2(0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f))};
}

glm::vec3 cubeDirection(int face, glm::vec2 st) {
    const float sc = 2.0f * st.x - 1.0f, tc = 2.0f * st.y - 1.0f;
    switch (face) {
    case 0:
        return {1.0f, -tc, -sc};
    case 1:
        return {-1.0f, -tc, sc};
    case 2:
        return {sc, 1.0f, tc};
    case 3:
        return {sc, -1.0f, -tc};
    case 4:
        return {sc, -tc, 1.0f};
    default:
        return {-sc, -tc, -1.0f};
    }
}

float texelSolidAngle(int size, int s, int t) {
    // ∫∫ dA / (1 + x² + y²)^(3/2) over the texel = F(x1,y1) - F(x0,y1) - F(x1,y0) + F(x0,y0) with
    // F(x, y) = atan2(xy, √(x² + y² + 1)).
    auto area = [](float x, float y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0f)); };
    const float inv = 2.0f / float(size);
    const float x0 = float(s) * inv - 1.0f, x1 = x0 + inv;
    const float y0 = float(t) * inv - 1.0f, y1 = y0 + inv;
    return area(x1, y1) - area(x0, y1) - area(x1, y0) + area(x0, y0);
}

glm::vec2 equirectCoord(glm::vec3 d) {
    d = glm::normalize(d);
    const float u = 0.5f - std::atan2(d.y, d.x) / (2.0f * kPi);
    const float v = 0.5f - std::asin(std::clamp(d.z, -1.0f, 1.0f)) / kPi;
    return {u - std::floor(u), v};
}

CubeImage cubeFromEquirect(const std::vector<glm::vec3>& pixels, int width, int height, int size) {
    if (width <= 0 || height <= 0 || pixels.size() != std::size_t(width) * height)
        throw std::invalid_argument("sgfx: cubeFromEquirect: " + std::to_string(width) + " x " +
                                    std::to_string(height) + " image with " + std::to_string(pixels.size()) +
                                    " pixels");
    // Each cube texel averages the image over its footprint (4 × 4 bilinear taps), so a large
    // panorama does not alias into a small cube.
    auto at = [&](glm::vec2 uv) {
        const float x = uv.x * float(width) - 0.5f,
                    y = std::clamp(uv.y * float(height) - 0.5f, 0.0f, float(height - 1));
        const int x0 = int(std::floor(x)), y0 = int(y);
        const float fx = x - float(x0), fy = y - float(y0);
        auto px = [&](int xi, int yi) {
            return pixels[std::size_t(std::min(yi, height - 1)) * width +
                          std::size_t(((xi % width) + width) % width)];
        };
        return glm::mix(glm::mix(px(x0, y0), px(x0 + 1, y0), fx),
                        glm::mix(px(x0, y0 + 1), px(x0 + 1, y0 + 1), fx), fy);
    };
    CubeImage c = CubeImage::filled(size, glm::vec3(0.0f));
    constexpr int kTaps = 4;
    for (int f = 0; f < 6; ++f)
        for (int t = 0; t < size; ++t)
            for (int s = 0; s < size; ++s) {
                glm::vec3 sum(0.0f);
                for (int j = 0; j < kTaps; ++j)
                    for (int i = 0; i < kTaps; ++i) {
                        const glm::vec2 st((float(s) + (float(i) + 0.5f) / kTaps) / float(size),
                                           (float(t) + (float(j) + 0.5f) / kTaps) / float(size));
                        sum += at(equirectCoord(cubeDirection(f, st)));
                    }
                c.texel(f, s, t) = sum / float(kTaps * kTaps);
            }
    return c;
}

std::array<float, 9> shBasis(glm::vec3 d) {
    return {0.282095f,
            0.488603f * d.y,
            0.488603f * d.z,
            0.488603f * d.x,
            1.092548f * d.x * d.y,
            1.092548f * d.y * d.z,
            0.315392f * (3.0f * d.z * d.z - 1.0f),
            1.092548f * d.x * d.z,
            0.546274f * (d.x * d.x - d.y * d.y)};
}

Sh9 irradianceSh(const CubeImage& radiance) {
    Sh9 sh{};
    for (int f = 0; f < 6; ++f)
        for (int t = 0; t < radiance.size; ++t)
            for (int s = 0; s < radiance.size; ++s) {
                const glm::vec3 d =
                    glm::normalize(cubeDirection(f, glm::vec2((float(s) + 0.5f) / float(radiance.size),
                                                              (float(t) + 0.5f) / float(radiance.size))));
                const float w = texelSolidAngle(radiance.size, s, t);
                const std::array<float, 9> y = shBasis(d);
                for (std::size_t i = 0; i < 9; ++i)
                    sh[i] += radiance.texel(f, s, t) * (y[i] * w);
            }
    // Â_l / π: the cosine lobe's convolution (π, 2π/3, π/4) and sgfx's light convention (1/π).
    const float band[9] = {1.0f, 2.0f / 3.0f, 2.0f / 3.0f, 2.0f / 3.0f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f};
    for (std::size_t i = 0; i < 9; ++i)
        sh[i] *= band[i];
    return sh;
}

glm::vec3 evalSh(const Sh9& sh, glm::vec3 n) {
    const std::array<float, 9> y = shBasis(glm::normalize(n));
    glm::vec3 e(0.0f);
    for (std::size_t i = 0; i < 9; ++i)
        e += sh[i] * y[i];
    return glm::max(e, glm::vec3(0.0f)); // order 2 rings slightly negative behind a bright sun
}

glm::vec2 hammersley(std::uint32_t i, std::uint32_t n) {
    std::uint32_t bits = i;
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return {float(i) / float(n), float(bits) * 2.3283064365386963e-10f};
}

namespace {
// One texel of a prefiltered level: the GGX lobe around N = V = R (Karis 2013, PrefilterEnvMap)
// with each sample read from the source mip of matching solid angle.
glm::vec3 prefilterTexel(const std::vector<CubeImage>& mips, glm::vec3 n, float alpha, int samples) {
    glm::vec3 t, b;
    basis(n, t, b);
    const float texelAngle = 4.0f * kPi / (6.0f * float(mips[0].size) * float(mips[0].size));
    glm::vec3 sum(0.0f);
    float weight = 0.0f;
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 hl = ggxHalfVector(hammersley(std::uint32_t(i), std::uint32_t(samples)), alpha);
        const glm::vec3 h = t * hl.x + b * hl.y + n * hl.z;
        const glm::vec3 l = 2.0f * glm::dot(n, h) * h - n;
        const float NdotL = glm::dot(n, l);
        if (NdotL <= 0.0f) continue;
        // pdf(L) = D·N·H / (4 V·H) = D/4 with V = N.
        const float pdf = ggxD(hl.z, alpha) / 4.0f;
        const float sampleAngle = 1.0f / (float(samples) * pdf + 1e-6f);
        const float lod =
            std::clamp(0.5f * std::log2(sampleAngle / texelAngle) + 1.0f, 0.0f, float(mips.size() - 1));
        const int l0 = int(lod);
        const int l1 = std::min(l0 + 1, int(mips.size()) - 1);
        const glm::vec3 c =
            glm::mix(mips[std::size_t(l0)].sample(l), mips[std::size_t(l1)].sample(l), lod - float(l0));
        sum += c * NdotL;
        weight += NdotL;
    }
    return weight > 0.0f ? sum / weight : glm::vec3(0.0f);
}
} // namespace

std::vector<CubeImage> prefilterSpecular(const CubeImage& radiance, int samples) {
    if (radiance.size < 8 || (radiance.size & (radiance.size - 1)))
        throw std::invalid_argument("sgfx: prefilterSpecular: the cube's size " +
                                    std::to_string(radiance.size) + " is not a power of two of at least 8");
    std::vector<CubeImage> sourceMips{radiance};
    while (sourceMips.back().size > 1)
        sourceMips.push_back(sourceMips.back().downsampled());
    const int levels = int(std::log2(float(radiance.size))) - 1; // down to 4 × 4
    std::vector<CubeImage> out{radiance};
    for (int level = 1; level < levels; ++level) {
        const int size = radiance.size >> level;
        CubeImage c = CubeImage::filled(size, glm::vec3(0.0f));
        const float alpha = alphaOf(levelRoughness(level, levels));
        for (int f = 0; f < 6; ++f)
            for (int t = 0; t < size; ++t)
                for (int s = 0; s < size; ++s) {
                    const glm::vec3 n = glm::normalize(cubeDirection(
                        f, glm::vec2((float(s) + 0.5f) / float(size), (float(t) + 0.5f) / float(size))));
                    c.texel(f, s, t) = prefilterTexel(sourceMips, n, alpha, samples);
                }
        out.push_back(std::move(c));
    }
    return out;
}

glm::vec2 brdfScaleBias(float NdotV, float roughness, int samples) {
    NdotV = std::max(NdotV, 1e-4f);
    const glm::vec3 v(std::sqrt(1.0f - NdotV * NdotV), 0.0f, NdotV);
    const float alpha = alphaOf(roughness);
    const float a2 = alpha * alpha;
    glm::vec2 ab(0.0f);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h = ggxHalfVector(hammersley(std::uint32_t(i), std::uint32_t(samples)), alpha);
        const float VdotH = glm::dot(v, h);
        const glm::vec3 l = 2.0f * VdotH * h - v;
        const float NdotL = l.z;
        if (NdotL <= 0.0f || VdotH <= 0.0f) continue;
        // f·cosθ / pdf with pdf = D·N·H / (4 V·H): the D cancels, leaving Vis·4·V·H·N·L / N·H.
        const float vis = 0.5f / (NdotL * std::sqrt(NdotV * NdotV * (1.0f - a2) + a2) +
                                  NdotV * std::sqrt(NdotL * NdotL * (1.0f - a2) + a2));
        const float gVis = vis * 4.0f * VdotH * NdotL / h.z;
        const float fc = std::pow(1.0f - VdotH, 5.0f);
        ab += glm::vec2((1.0f - fc) * gVis, fc * gVis);
    }
    return ab / float(samples);
}

std::vector<glm::vec2> brdfTable(int size, int samples) {
    std::vector<glm::vec2> table(std::size_t(size) * size);
    for (int i = 0; i < size; ++i)
        for (int j = 0; j < size; ++j)
            table[std::size_t(i) * size + j] =
                brdfScaleBias((float(j) + 0.5f) / float(size), (float(i) + 0.5f) / float(size), samples);
    return table;
}

} // namespace sgfx::env
