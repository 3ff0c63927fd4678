// The scalar type of the per-pixel maths on nondimensional inputs (`*_nd` modules, fresnel).
// The renderer composes it as f32. The conformance harness (core/src/shading/conformance.rs)
// also composes the same modules with flag REAL_F16, after `enable f16;`, to measure what a
// mobile GPU's half precision would do; nothing in the renderer ever sets that flag.
#ifdef REAL_F16
alias real = f16;
#else
alias real = f32;
#endif

// π and 1/π as abstract constants, so they take the type of `real`.
const ND_PI = 3.14159265358979;
const ND_INV_PI = 0.318309886183791;
