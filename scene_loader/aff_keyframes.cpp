#include "scene_loader/aff_keyframes.h"

#include <vector>

namespace rtsim::aff {

namespace {

long key_count(Tokenizer& tk, const char* kind) {
  long n = tk.count("number of keys");
  // The first and last keys only shape tangents, so 4 is the minimum (as in BART).
  if (n < 4) tk.fail(std::to_string(n), std::string("at least 4 '") + kind + "' keys");
  return n;
}

Tcb read_tcb(Tokenizer& tk) {
  Tcb c;
  c.tension = tk.number("key tension");
  c.continuity = tk.number("key continuity");
  c.bias = tk.number("key bias");
  return c;
}

// Keys are added as the file shows them, never allocated from the count it states: a count no
// file could hold ends with the file, as an error, not as an allocation of that size.
std::vector<KbKey<dvec3>> read_vector_keys(Tokenizer& tk, const char* kind) {
  const long n = key_count(tk, kind);
  std::vector<KbKey<dvec3>> keys;
  for (long i = 0; i < n; ++i) {
    KbKey<dvec3>& k = keys.emplace_back();
    k.time = tk.number("key time");
    k.value = tk.vec3("key x y z");
    k.tcb = read_tcb(tk);
  }
  return keys;
}

std::vector<KbKey<dquat>> read_rotation_keys(Tokenizer& tk) {
  const long n = key_count(tk, "rot");
  std::vector<KbKey<dquat>> keys;
  for (long i = 0; i < n; ++i) {
    KbKey<dquat>& k = keys.emplace_back();
    k.time = tk.number("key time");
    dvec3 axis = tk.vec3("rotation key axis");
    // Each key is an absolute orientation; angles beyond 360 only matter modulo 720 here.
    k.value = quat_from_axis_angle(axis, tk.number("rotation key angle in degrees"));
    k.tcb = read_tcb(tk);
  }
  return keys;
}

}  // namespace

// `k NAME { transl N ... rot N ... scale N ... visibility N ... }`, evaluated right away:
// the load time is fixed, so only the resulting transform needs keeping.
Animation parse_keyframes(Tokenizer& tk, double time, KbQuatSpline::Flip rotation_flip,
                          std::string& name) {
  name = std::string(tk.word("an animation name after 'k'"));
  tk.expect("{", "after 'k NAME'");
  Animation anim;
  for (;;) {
    std::string_view kind = tk.next();
    if (kind == "}") break;
    if (kind == "transl" || kind == "scale") {
      bool is_transl = kind == "transl";
      KbSpline<dvec3> spline(read_vector_keys(tk, is_transl ? "transl" : "scale"));
      (is_transl ? anim.translation : anim.scale) = spline.evaluate(time);
      if (is_transl) anim.has_translation = true;
    } else if (kind == "rot") {
      anim.rotation = KbQuatSpline(read_rotation_keys(tk), rotation_flip).evaluate(time);
      anim.has_rotation = true;
    } else if (kind == "visibility") {
      // Visible until the first key; from each key's time on, that key's flag holds.
      long n = tk.count("number of visibility keys");
      if (n < 1) tk.fail(std::to_string(n), "at least 1 visibility key");
      for (long i = 0; i < n; ++i) {
        double t = tk.number("visibility key time");
        long flag = tk.integer("visibility flag 0 or 1");
        if (flag != 0 && flag != 1) tk.fail(std::to_string(flag), "visibility flag 0 or 1");
        if (t <= time) anim.visible = flag == 1;
      }
    } else {
      tk.fail(kind, "'transl', 'rot', 'scale', 'visibility' or '}' in 'k " + name + "'");
    }
  }
  return anim;
}

}  // namespace rtsim::aff
