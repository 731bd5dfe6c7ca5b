// OSG's intensity map (readIntensityImage, OSG src/osgWrappers/deprecated-dotosg/osgViewer/View.cpp):
// piecewise linear in the angle between (angle°, percent) points, the end values held beyond them.
uniform int sphere_intensityCount; // 0: no map, intensity 1
uniform vec2 sphere_intensity[32];

float sphereIntensity(float angle) {
    if (sphere_intensityCount <= 0) return 1.0;
    vec2 first = sphere_intensity[0], last = sphere_intensity[sphere_intensityCount - 1];
    if (angle <= first.x) return first.y * 0.01;
    if (angle >= last.x) return last.y * 0.01;
    for (int i = 1; i < sphere_intensityCount; ++i) {
        vec2 a = sphere_intensity[i - 1], b = sphere_intensity[i];
        if (angle <= b.x) return mix(a.y, b.y, (angle - a.x) / (b.x - a.x)) * 0.01;
    }
    return last.y * 0.01;
}
