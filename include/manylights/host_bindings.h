// The binding contract of manylights/manylights.glsl, the include through which a host's own shaders
// (forward, transparent, decal passes) read the module's lights and shadows, and which the module's own
// evaluation pass uses too. One definition for GLSL (the include declares its buffers
// at ML_LIGHTS_BINDING + these offsets, in descriptor set ML_LIGHTS_SET) and C++ (Module::
// hostShaderBindings fills one HostShaderBuffer per offset, in this order).
//
// Offset  GLSL block (instance)               descriptor type  per frame slot or shared
//   0     MlFrame { FrameConstants frame }    uniform          slot   camera, size, cluster grid
//   1     MlSlices { float sliceFar[] }       storage          slot   cluster depth-slice ends
//   2     MlLights { GpuLight lights[] }      storage          slot   the frame's visible lights
//   3     MlRanges { uvec2 ranges[] }         storage          shared cluster lists (offset, count)
//   4     MlPool { uint pool[] }              storage          shared light indices of the lists
//   5     MlStaticWords { uint staticWords[] } storage         shared static bakes (every method)
//   6     MlShadowRecords { GpuShadowRecord shadowRecords[] } storage slot  static records per light
//   7     MlVsmConst { VsmConstants vsm }     uniform          slot   virtual shadow map constants
//   8     MlVsmMaps { GpuVsmMap vsmMaps[] }   storage          slot   virtual shadow maps of the frame
//   9     MlVsmCoverage { uint vsmCoverage[] } storage         slot   pages under dynamic casters
//  10     MlVsmTable { uint vsmTable[] }      storage          shared page table
//  11     MlVsmPool { uint vsmPool[] }        storage          shared physical page texels
// "Shared" buffers are rewritten by the next frame's passes (ordered by its frame-begin barrier), so a
// host reads this frame's contents only between this record() and the next in queue order; "slot"
// buffers by the host side of the next record() that reuses the slot.
#ifndef ML_HOST_BINDINGS_H
#define ML_HOST_BINDINGS_H

#define ML_HOST_FRAME 0
#define ML_HOST_SLICES 1
#define ML_HOST_LIGHTS 2
#define ML_HOST_RANGES 3
#define ML_HOST_POOL 4
#define ML_HOST_STATIC_WORDS 5
#define ML_HOST_SHADOW_RECORDS 6
#define ML_HOST_VSM_CONST 7
#define ML_HOST_VSM_MAPS 8
#define ML_HOST_VSM_COVERAGE 9
#define ML_HOST_VSM_TABLE 10
#define ML_HOST_VSM_POOL 11
// 12 bindings, 10 storage and 2 uniform buffers: the evaluation pass binds the same 12 (plus its five
// images) on every device the module runs on, so a host stage that adds a few of its own stays within
// maxPerStageDescriptorStorageBuffers / UniformBuffers there.
#define ML_HOST_BINDING_COUNT 12

#endif
