// lightVisibility*() in terms of the technique's lightAttenuate*(): included at the end of
// every shadow technique's visibility.glsl, after it defines lightAttenuate() and
// lightAttenuateInMedium(). Receivers that need the value rather than the in-place form
// (docs/architecture.md, "Two GLSL interfaces") call these.
vec3 lightVisibility(int i, vec3 P, vec3 N, vec3 L) {
    vec3 v = vec3(1.0);
    lightAttenuate(i, P, N, L, v);
    return v;
}

vec3 lightVisibilityInMedium(int i, vec3 P) {
    vec3 v = vec3(1.0);
    lightAttenuateInMedium(i, P, v);
    return v;
}
