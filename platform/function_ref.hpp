// FunctionRef<R(Args...)>: a non-owning reference to a callable, two pointers
// wide, never allocating. Used where std::function would heap-allocate a
// capturing lambda on every call (ThreadPool::run runs once per frame stage).
//
// It does not extend the callable's lifetime: binding a temporary lambda is
// fine for a call that completes before the full expression ends
// (pool.run([&](int w) { ... });), storing the FunctionRef is not. Plain
// functions and function pointers are stored by value, so
// FunctionRef<int(int)> f(&g); is safe to keep.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>

namespace tristereo {

template <typename Signature>
class FunctionRef;

template <typename R, typename... Args>
class FunctionRef<R(Args...)> {
  template <typename F>
  static constexpr bool is_function_pointer =
      std::is_pointer<std::decay_t<F>>::value &&
      std::is_function<std::remove_pointer_t<std::decay_t<F>>>::value;

 public:
  template <typename F,
            typename = std::enable_if_t<
                !std::is_same<std::decay_t<F>, FunctionRef>::value &&
                std::is_invocable_r<R, F&, Args...>::value>>
  FunctionRef(F&& f) noexcept {  // NOLINT(google-explicit-constructor): call sites pass lambdas
    if constexpr (is_function_pointer<F>) {
      // A pointer passed as a temporary would dangle; keep the pointer itself.
      std::decay_t<F> fn = f;
      target_.function = reinterpret_cast<void (*)()>(fn);
      call_ = &call_function<std::decay_t<F>>;
    } else {
      target_.object = const_cast<void*>(static_cast<const void*>(std::addressof(f)));
      call_ = &call_object<std::remove_reference_t<F>>;
    }
  }

  R operator()(Args... args) const { return call_(target_, std::forward<Args>(args)...); }

 private:
  union Target {
    void* object;
    void (*function)();
  };

  template <typename F>
  static R call_object(Target target, Args... args) {
    return (*static_cast<F*>(target.object))(std::forward<Args>(args)...);
  }

  template <typename Fn>
  static R call_function(Target target, Args... args) {
    return reinterpret_cast<Fn>(target.function)(std::forward<Args>(args)...);
  }

  Target target_;
  R (*call_)(Target, Args...);
};

}  // namespace tristereo
