const float PI = 3.14159265358979323846;
float saturate(float x) { return clamp(x, 0.0, 1.0); }
float maxComponent(vec3 v) { return max(v.x, max(v.y, v.z)); }
