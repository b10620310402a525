#pragma once
// A condition whose stimulus is a physical object in the room rather than an image: its scene
// column reads "real:" and the object's name, e.g. "real:desk lamp". Luidolt 2020, section 7.2:
// the observer first looks at a real desk lamp in the darkened lab, then rates the simulation of
// it. The session shows an instruction naming the object instead of an image (no glare, no
// perception stage: nothing is rendered), and the observer answers as for any other condition.
// Only a rating can present such a stimulus; the experiment-file reader refuses it elsewhere.
// In the base layer because protocols/ (the check at load), runner/ (the instruction frame) and
// analysis/ (telling real conditions apart in the trials) read the same spelling.
#include <string>
#include <string_view>

namespace glarelab {

inline constexpr std::string_view kRealStimulusPrefix = "real:";

// True when `scene` starts with "real:" (case as written: "Real:" is an ordinary scene name).
bool is_real_stimulus(std::string_view scene);

// The object's name: the text after "real:" without surrounding blanks ("real: desk lamp " ->
// "desk lamp"); empty when `scene` is not a real stimulus or names no object.
std::string real_stimulus_object(std::string_view scene);

// What the session shows instead of an image: "Look at the real desk lamp, then answer."
std::string real_stimulus_instruction(std::string_view object);

}  // namespace glarelab
