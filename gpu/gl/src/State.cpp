// Applies a whole PipelineState. Every field is set every time: the state a pass sees depends only
// on its own PipelineState, never on which pass ran before it.
#include <gpu/gl/State.h>

namespace gpu {

namespace {

void setCap(GLenum cap, bool on) {
    if (on) {
        glEnable(cap);
    } else {
        glDisable(cap);
    }
}

void applyStencilFace(GLenum face, const StencilFace& s) {
    glStencilFuncSeparate(face, s.func, s.ref, s.readMask);
    glStencilOpSeparate(face, s.stencilFail, s.depthFail, s.depthPass);
}

} // namespace

void applyState(const PipelineState& state) {
    setCap(GL_DEPTH_TEST, state.depthTest);
    glDepthFunc(state.depthFunc);
    // Depth and colour masks also gate glClear: a pass that clears sets them itself.
    glDepthMask(state.depthWrite ? GL_TRUE : GL_FALSE);
    if (state.independentTargets) {
        for (GLuint i = 0; i < kMaxColorTargets; ++i) {
            const ColorTargetState& t = state.targets[i];
            if (t.blend) {
                glEnablei(GL_BLEND, i);
            } else {
                glDisablei(GL_BLEND, i);
            }
            glBlendFunci(i, t.blendSrc, t.blendDst);
            glBlendEquationi(i, t.blendEquation);
            glColorMaski(i, t.writeR, t.writeG, t.writeB, t.writeA);
        }
    } else {
        GLboolean c = state.colorWrite ? GL_TRUE : GL_FALSE;
        glColorMask(c, c, c, c);
        setCap(GL_BLEND, state.blend);
        glBlendFunc(state.blendSrc, state.blendDst);
        glBlendEquation(state.blendEquation);
    }

    setCap(GL_STENCIL_TEST, state.stencilTest);
    applyStencilFace(GL_FRONT, state.stencilFront);
    applyStencilFace(GL_BACK, state.stencilBack);
    glStencilMask(state.stencilWriteMask);

    setCap(GL_CULL_FACE, state.cull);
    glCullFace(state.cullFace);

    glPolygonMode(GL_FRONT_AND_BACK, state.polygonMode);
    setCap(GL_POLYGON_OFFSET_FILL, state.polygonOffset);
    setCap(GL_POLYGON_OFFSET_LINE, state.polygonOffset);
    glPolygonOffset(state.polygonOffsetFactor, state.polygonOffsetUnits);

    setCap(GL_COLOR_LOGIC_OP, state.logicOp);
    glLogicOp(state.logicOpMode);

    setCap(GL_DEPTH_CLAMP, state.depthClamp);
    setCap(GL_SCISSOR_TEST, state.scissor);
    if (state.scissor)
        glScissor(state.scissorRect.x, state.scissorRect.y, state.scissorRect.width,
                  state.scissorRect.height);
}

} // namespace gpu
