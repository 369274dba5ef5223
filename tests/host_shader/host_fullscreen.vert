#version 460
// A full-screen triangle for host_forward.frag, without a vertex buffer: vertices (-1,-1), (3,-1),
// (-1,3) in clip space, so every pixel of the viewport gets one fragment at its centre (one primitive:
// no seam where two triangles of a quad would share pixel centres). No depth attachment is bound.
void main() {
    vec2 p = vec2((gl_VertexIndex & 1) * 4 - 1, (gl_VertexIndex >> 1) * 4 - 1);
    gl_Position = vec4(p, 0.0, 1.0);
}
