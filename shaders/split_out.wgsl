// What a pass writes in a frame with the subsurface pass (`render/passes/subsurface.rs`: its
// three targets, `SPLIT_FORMAT`): the radiance that stays (rgb) with the skin marker (a: 1
// skin, 0 not), the irradiance the pass spreads (rgb) with the pixel's size in mm (a), and the
// exit factor per channel (rgb), which turns the spread exitance into radiance toward the
// viewer. The character, the props and the blob shadows write it (each its own way).

struct SplitOut {
    @location(0) colour: vec4<f32>,
    @location(1) spread: vec4<f32>,
    @location(2) exit: vec4<f32>,
};
