#include "core/gl/gl_context.h"

namespace glarelab {

std::string GlInfo::describe() const {
  return "OpenGL " + version + " on " + renderer + " (" + vendor + ")" + (platform.empty() ? "" : " via " + platform);
}

namespace {

class ContextHandle final : public GlContext {
 public:
  explicit ContextHandle(GlContext& context) : context_(context) {}
  const GlInfo& gl_info() const override { return context_.gl_info(); }
  void make_current() override { context_.make_current(); }

 private:
  GlContext& context_;
};

}  // namespace

GlContextFactory one_context_factory(GlContext& context) {
  return [&context]() -> std::unique_ptr<GlContext> {
    context.make_current();  // a factory's context is current when made
    return std::make_unique<ContextHandle>(context);
  };
}

}  // namespace glarelab
