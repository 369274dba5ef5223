// Binding numbers of mip_reduce.comp, named once for the shader and for the C++ that binds each image
// view by its binding's name (ML_BIND, gpu/bindings.h; tests/gpu/image_mips_test.cpp).
#ifndef ML_MIP_REDUCE_BINDINGS_H
#define ML_MIP_REDUCE_BINDINGS_H

#define ML_MIP_REDUCE_SRC 0 // mip m - 1 of every layer (R32_UINT storage, GENERAL)
#define ML_MIP_REDUCE_DST 1 // mip m

#endif
