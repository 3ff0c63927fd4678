// The scalar type of the per-pixel maths on nondimensional inputs (`*_nd` modules, fresnel).
// The renderer composes it as f32. The conformance harness (measure/src/conformance/harness.rs)
// also composes the same modules with flag REAL_F16, after `enable f16;`, to measure what a
// mobile GPU's half precision would do; nothing in the renderer ever sets that flag. The
// constants they read (PI, INV_PI, the lobe's floors) are abstract, so they take its type.
#import consts

#ifdef REAL_F16
alias real = f16;
#else
alias real = f32;
#endif
