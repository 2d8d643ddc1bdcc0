// Emitted radiance of volumes with an emission channel (emission x density, x the emission
// grid's value or rgb, or the blackbody radiance of the temperature grid): the model of the
// CPU's integrators/emission.h emittedRadiance(). Included under VEIL_VOLUME_EMISSION by the fog
// (fog_medium.glsl) and by the scattered-light cache's bake (cache_bake.comp).
// Emission channels (src/fog/fog_pass.cpp): per volume a texture of the density's layout,
// and the blackbody table (src/integrators/blackbody.h blackbodyTable(): linear sRGB / Y and ln Y at
// T = i x blackbodyMaxKelvin / (size - 1)).
layout(binding = VEIL_TEX_VOLUME_EMISSION) uniform sampler3D volumeEmission[VEIL_VOLUME_SLOTS];
layout(binding = VEIL_TEX_BLACKBODY) uniform sampler1D blackbodyTable;
uniform float blackbodyMaxKelvin;

// Planck radiance at `kelvin` integrated against the CIE 1931 functions, linear sRGB
// (kW m^-2 sr^-1); clamped to the table's last entry above blackbodyMaxKelvin.
vec3 blackbodyRadiance(float kelvin) {
    if (kelvin <= 0.0) return vec3(0.0);
    float n = float(textureSize(blackbodyTable, 0));
    vec4 c = texture(blackbodyTable, (kelvin / blackbodyMaxKelvin * (n - 1.0) + 0.5) / n);
    return c.rgb * exp(c.a);
}

// Radiance emitted per unit length by volume i at texture coordinate uvw (density d).
vec3 volumeEmitted(int i, float d, vec3 uvw) {
    if (volumes[i].emissionMode == 0) return d * volumes[i].emission;
    vec4 e = texture(volumeEmission[i], uvw);
    if (volumes[i].emissionMode == 3) return e.rgb * volumes[i].emission; // colour grid
    float c = e.r;
    if (volumes[i].emissionMode == 1) return c * volumes[i].emission;
    vec3 t = volumes[i].temperature;
    return d * (volumes[i].emission + t.z * blackbodyRadiance(t.x * c + t.y));
}
