// Emitted radiance per unit length of a volume with an emission channel, for the scattered-light
// cache's bake (cache_bake.comp): the model of fog_medium.glsl volumeEmitted() and of the CPU's
// integrators/emission.h emittedRadiance() (emission x density, x the emission grid's value or
// rgb, or the blackbody radiance of the temperature grid).
layout(binding = VEIL_TEX_VOLUME_EMISSION) uniform sampler3D volumeEmission[VEIL_VOLUME_SLOTS];
layout(binding = VEIL_TEX_BLACKBODY) uniform sampler1D blackbodyTable;
uniform float blackbodyMaxKelvin;

// Planck radiance at `kelvin` (linear sRGB) from the table of src/integrators/blackbody.h
// blackbodyTable(): rgb / Y and ln Y at T = i x blackbodyMaxKelvin / (size - 1).
vec3 cacheBlackbody(float kelvin) {
    if (kelvin <= 0.0) return vec3(0.0);
    float n = float(textureSize(blackbodyTable, 0));
    vec4 c = texture(blackbodyTable, (kelvin / blackbodyMaxKelvin * (n - 1.0) + 0.5) / n);
    return c.rgb * exp(c.a);
}

// Volume i at texture coordinate uvw with (clamped) density d.
vec3 cacheEmitted(int i, float d, vec3 uvw) {
    if (volumes[i].emissionMode == 0) return d * volumes[i].emission;
    vec4 e = texture(volumeEmission[i], uvw);
    if (volumes[i].emissionMode == 3) return e.rgb * volumes[i].emission;
    if (volumes[i].emissionMode == 1) return e.r * volumes[i].emission;
    vec3 t = volumes[i].temperature;
    return d * (volumes[i].emission + t.z * cacheBlackbody(t.x * e.r + t.y));
}
