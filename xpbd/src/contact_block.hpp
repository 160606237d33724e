#pragma once
// The joint solve of one particle's body contacts (internal to xpbd).
#include <cstddef>

#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd::rigid {

// Contacts of one particle: at most this many are solved jointly.
inline constexpr int kMaxJointContacts = 4;
// Attachments of the same particle that join them (the first ones; any
// others keep their own stage).
inline constexpr int kMaxJointAttachments = 2;

// Solves the normal parts of the contacts of one particle jointly: the chain
// starting at contact `head` (State::contact_head/contact_next), as one small
// projected linear complementarity problem, exactly (every active set is
// tried), with the particle's attachments as equality rows
// (State::contact_attachment). Returns false, changing nothing, if the
// chain is longer than kMaxJointContacts or no active set solves it
// (degenerate input); the caller then solves the contacts one by one.
bool solve_contact_group(const Model& m, State& s, std::size_t head, Real inv_h2);

// The friction of the same chain, jointly (static friction with a clamp to
// the dynamic cone; contact_block.cpp), for the contacts that push and have
// friction, with the particle's attachments; each contact gets
// ContactLambda::joint. Returns false, changing nothing, if there are fewer
// than two such contacts and attachments together, none such contact, more
// than kMaxJointContacts, or a degenerate input; the caller then solves the
// friction one by one.
bool solve_friction_group(const Model& m, State& s, std::size_t head, Real inv_h2);

}  // namespace xpbd::rigid
