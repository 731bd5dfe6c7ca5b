in vec3 v_direction;
in float v_angle;
// xy: the image centre, z: its radius (pixels); w > 0: the intensity angle is the pixel's own
// (3D display: 180° × distance / radius, clamped), not the mesh's interpolated one.
uniform vec4 sphere_pixelAngle;
layout(location = 0) out vec4 fragOut;
void main() {
    float angle = v_angle;
    if (sphere_pixelAngle.w > 0.0)
        angle = min(length(gl_FragCoord.xy - sphere_pixelAngle.xy) / sphere_pixelAngle.z, 1.0) * 180.0;
    fragOut = vec4(sphereScene(normalize(v_direction)) * sphereIntensity(angle), 1.0);
}
