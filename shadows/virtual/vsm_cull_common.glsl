// Culling against a map shared by vsm_cull.comp (instances, vertex path), vsm_expand.comp (instances,
// mesh path) and vsm_draw.task (meshlets): frustum, projected bounds, and the hierarchical page buffer
// test (RMVSM section 4.3). The including shader declares `vsm` (VsmConstants), `vsmTable[]` and the HPB
// bits `vsmHpb[]` (uint[], VsmConstants.order.w words per map slot, layout in vsm_math.h), unless it
// defines VSM_NO_PAGES (vsm_pairs); with VSM_CASTER_GROUPS, the caster-group test (vsmGroupMayDraw).
#ifndef ML_VSM_CULL_COMMON_GLSL
#define ML_VSM_CULL_COMMON_GLSL

// The six planes of viewProj (Vulkan depth 0..1), unnormalised: inside when dot(n, p) + w >= 0.
void vsmFrustumPlanes(mat4 viewProj, out vec4 planes[6]) {
    mat4 M = transpose(viewProj); // rows of viewProj as columns
    planes = vec4[6](M[3] + M[0], M[3] - M[0], M[3] + M[1], M[3] - M[1], M[2], M[3] - M[2]);
}

// A world box against the frustum (the far plane is the light's range): false when it is behind one plane.
// A closed caster whose box lies wholly in front of the map's near plane: its back faces (seen from the
// light) may be culled, since the nearest surface along any ray from the light is then a front face
// (with the box crossing the near plane, a clipped front face could leave a back face nearest).
bool vsmClosedInFront(GpuVsmMap m, GpuCaster c) {
    if (c.meshlets.z == 0u) return false;
    float zmin = 1e30;
    for (uint k = 0u; k < 8u; ++k) {
        vec3 p = vec3((k & 1u) != 0u ? c.hi.x : c.lo.x, (k & 2u) != 0u ? c.hi.y : c.lo.y,
                      (k & 4u) != 0u ? c.hi.z : c.lo.z);
        zmin = min(zmin, -vsmPoint(m.view, p).z);
    }
    return zmin > m.params.y * 1.001 + 1e-4;
}

// `precise` (no contraction): rounded products and sums are monotone, so a box inside another never
// passes a plane the larger one fails (vsmGroupMayDraw relies on it).
bool vsmBoxInFrustum(vec4 planes[6], vec3 lo, vec3 hi) {
    for (uint k = 0u; k < 6u; ++k) {
        vec3 n = planes[k].xyz;
        vec3 far = vec3(n.x >= 0.0 ? hi.x : lo.x, n.y >= 0.0 ? hi.y : lo.y, n.z >= 0.0 ? hi.z : lo.z);
        precise float x = n.x * far.x, y = n.y * far.y, z = n.z * far.z;
        precise float d = x + y + z + planes[k].w;
        if (d < 0.0) return false;
    }
    return true;
}

#ifdef VSM_CASTER_GROUPS
// The includer declares vsmMaps[], vsmDirtyMips[], vsmCasterGroups[] (vsm_groups.comp) and vsmCounters
// (groupTests, groupsRefused). Whether some
// caster of `group` may be drawn into `map`: the map has a dirty mip, the group has casters the map takes
// (dynamic ones for a baked light's map) and their box is inside the map's frustum. `refusedMeshlets`:
// the meshlets x dirty mips the frustum refused (vsm_expand's counters count each caster's).
bool vsmGroupMayDraw(uint map, uint group, out uint refusedMeshlets) {
    refusedMeshlets = 0u;
    uint mipsDirty = vsmDirtyMips[map];
    if (mipsDirty == 0u) return false;
    bool dynamicOnly = (vsmMaps[map].info.y & ML_VSM_MAP_DYNAMIC_ONLY) != 0u;
    GpuCasterGroup g = vsmCasterGroups[group];
    if ((dynamicOnly ? g.counts.z : g.counts.x) == 0u) return false;
    vec4 planes[6];
    vsmFrustumPlanes(vsmMaps[map].viewProj, planes);
    atomicAdd(vsmCounters.groupTests, 1u);
    if (vsmBoxInFrustum(planes, dynamicOnly ? g.dynamicLo.xyz : g.lo.xyz, dynamicOnly ? g.dynamicHi.xyz : g.hi.xyz))
        return true;
    atomicAdd(vsmCounters.groupsRefused, 1u);
    refusedMeshlets = (dynamicOnly ? g.counts.w : g.counts.y) * bitCount(mipsDirty);
    return false;
}
#endif

// A world sphere against the frustum.
bool vsmSphereInFrustum(vec4 planes[6], vec3 c, float r) {
    for (uint k = 0u; k < 6u; ++k)
        if (dot(planes[k].xyz, c) + planes[k].w < -r * length(planes[k].xyz)) return false;
    return true;
}

// NDC rectangle of a world box's 8 corners, with one finest texel of slack (a triangle on the box's edge
// covers texel centres there); a corner behind the light covers the whole map.
void vsmProjectedBounds(mat4 viewProj, vec3 blo, vec3 bhi, out vec2 lo, out vec2 hi) {
    lo = vec2(1e30);
    hi = vec2(-1e30);
    bool behind = false;
    for (uint k = 0u; k < 8u; ++k) {
        vec3 p = vec3((k & 1u) != 0u ? bhi.x : blo.x, (k & 2u) != 0u ? bhi.y : blo.y, (k & 4u) != 0u ? bhi.z : blo.z);
        vec4 clip = viewProj * vec4(p, 1.0);
        if (clip.w <= 1e-6) { behind = true; break; }
        lo = min(lo, clip.xy / clip.w);
        hi = max(hi, clip.xy / clip.w);
    }
    if (behind) { lo = vec2(-1.0); hi = vec2(1.0); }
    lo -= vec2(2.0 / float(vsm.options.z));
    hi += vec2(2.0 / float(vsm.options.z));
}

#ifndef VSM_NO_PAGES // vsm_pairs reads neither the page table nor the HPB
bool vsmDirtyCell(uint map, uint mip, uint level, uint x, uint y) {
    uint s0 = vsm.page.z;
    if (level == 0u) return (vsmTable[vsmEntry(vsm.sizes.x, s0, map, mip, x, y)] & ML_VSM_DIRTY) != 0u;
    uint bit = map * vsm.order.w * 32u + vsmHpbBit(s0, mip, level, x, y);
    return (vsmHpb[bit >> 5u] & (1u << (bit & 31u))) != 0u;
}

// HPB test: any dirty page of `mip` under the NDC rectangle, read at the level where the rectangle spans
// at most 2x2 cells (so at most four reads).
// The pages of `mip` under an NDC rectangle, clamped to the map (inclusive corners p0, p1).
void vsmPageRect(uint mip, vec2 lo, vec2 hi, out ivec2 p0, out ivec2 p1) {
    int side = int(vsm.page.z >> mip);
    p0 = clamp(ivec2(floor((lo * 0.5 + 0.5) * float(side))), ivec2(0), ivec2(side - 1));
    p1 = clamp(ivec2(floor((hi * 0.5 + 0.5) * float(side))), ivec2(0), ivec2(side - 1));
}

// Whether a caster is drawn into page (x, y) of `mip`: the page is rendered this frame and, for a static
// caster, so is its static twin (a page redrawn from its twin takes only the dynamic casters: the
// static ones' depths are already in the copy).
bool vsmPageDrawn(uint map, uint mip, int x, int y, bool dynamicCaster) {
    uint pt = vsmTable[vsmEntry(vsm.sizes.x, vsm.page.z, map, mip, uint(x), uint(y))];
    return (pt & ML_VSM_DIRTY) != 0u && (dynamicCaster || (pt & ML_VSM_DIRTY_STATIC) != 0u ||
                                         (pt & ML_VSM_STATIC_VALID) == 0u);
}

bool vsmHpbAny(uint map, uint mip, vec2 lo, vec2 hi) {
    ivec2 p0, p1;
    vsmPageRect(mip, lo, hi, p0, p1);
    uint level = 0u;
    while ((p1.x >> level) - (p0.x >> level) > 1 || (p1.y >> level) - (p0.y >> level) > 1) ++level;
    for (int y = p0.y >> level; y <= (p1.y >> level); ++y)
        for (int x = p0.x >> level; x <= (p1.x >> level); ++x)
            if (vsmDirtyCell(map, mip, level, uint(x), uint(y))) return true;
    return false;
}

#endif // VSM_NO_PAGES

#endif
