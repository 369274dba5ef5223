// Binding numbers of the G-buffer draw (gbuffer.vert), named once for the shader and for
// engine/gbuffer.cpp, which binds each buffer by its name (ML_BIND, gpu/bindings.h).
#ifndef ML_GBUFFER_BINDINGS_H
#define ML_GBUFFER_BINDINGS_H

#define ML_GBUFFER_FRAME 0     // FrameConstants (uniform)
#define ML_GBUFFER_VERTICES 1  // GpuVertex, pulled by index
#define ML_GBUFFER_INSTANCES 2 // GpuInstance per draw (firstInstance)

#endif
