/* The gridworld learners of the chapter's Section 5.3 in plain C: the yardstick of the compiled
 * kernels' speed (benchmarks/bench_gridworld.py).
 *
 * Two agents, each with its own goal cells, the rules of glamas.gridworld.rules, eq. 11 with epsilon-greedy selection and random
 * tie-breaking, and for 2observe (Alg. 4) a GLA per agent (eq. 13-15) over the context [delta, 1],
 * need = "the agents could collide this step" and the feedback table[choice][need] minus
 * penalty * delta when both coordinated without need. Each run draws from the same xoshiro256**
 * stream as the kernels (glamas.rng), in the same order, and writes the same binned log
 * (glamas.learners.episode), so the two can be compared number for number.
 *
 * Built as a shared library (cc -O2 -shared -fPIC) and called through ctypes, so that both sides
 * are timed in one process. Arrays are C-contiguous: next_cell (cells x 4, int64), goal_of (2 x cells,
 * uint8: goal_of[i * cells + c], cell c is a goal of agent i), starts (2, int64), q (tables x states
 * x actions, double), log (blocks x 8, double).
 */

#include <math.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>

enum { STEPS = 0, REWARD = 2, LENGTH = 4, COLLISIONS = 5, COORDINATIONS = 6, CAPPED = 7, N_COLUMNS = 8 };
enum { N_ACTIONS = 4, BOUNCE_PREVIOUS = 0 };
/* The world and what it pays (glamas.gridworld.rewards.Rewards, read from the workload). */
typedef struct {
    const int64_t *next_cell;
    const uint8_t *goal_of;
    const int64_t *starts;
    int64_t bounce, n_cells, n_cols;
    double goal, move, bump, collision;
    int64_t collision_replaces_move;
} World;

typedef struct {
    int64_t cells[2], actions[2], new_cells[2];
    int done[2], reached[2];
    double rewards[2], acc[N_COLUMNS];
} Episode;

/* xoshiro256** (Blackman and Vigna), as glamas.rng. */
static inline uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static inline uint64_t next_u64(uint64_t *s) {
    uint64_t result = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

static inline double uniform(uint64_t *s) { return (double)(next_u64(s) >> 11) * (1.0 / 9007199254740992.0); }

static inline int64_t integer(uint64_t *s, int64_t n) {
    int64_t k = (int64_t)(uniform(s) * (double)n);
    return k < n - 1 ? k : n - 1;
}

/* argmax with ties broken uniformly at random (one draw, only on a tie). */
static int64_t greedy(const double *row, int64_t n, uint64_t *s) {
    double best = row[0];
    int64_t ties = 1, a, pick;
    for (a = 1; a < n; a++) {
        if (row[a] > best) { best = row[a]; ties = 1; }
        else if (row[a] == best) ties++;
    }
    pick = ties == 1 ? 0 : integer(s, ties);
    for (a = 0; a < n; a++)
        if (row[a] == best && pick-- == 0) return a;
    return n - 1;
}

static int64_t epsilon_greedy(const double *row, int64_t n, double exploit, uint64_t *s) {
    if (uniform(s) < exploit) return greedy(row, n, s);
    return integer(s, n);
}

/* Eq. 11 on a table with n actions per state. */
static void q_update(double *q, int64_t n, int64_t s, int64_t a, double r, int64_t s_next, int terminal,
                     double alpha, double gamma) {
    double target = r;
    if (!terminal) {
        const double *row = q + s_next * n;
        double best = row[0];
        for (int64_t b = 1; b < n; b++)
            if (row[b] > best) best = row[b];
        target += gamma * best;
    }
    q[s * n + a] = (1.0 - alpha) * q[s * n + a] + alpha * target;
}

static int is_goal_of(const World *w, int i, int64_t cell) { return w->goal_of[i * w->n_cells + cell]; }

/* A cell both agents' goal: entering it together is no collision. */
static int goal_of_both(const World *w, int64_t cell) { return is_goal_of(w, 0, cell) && is_goal_of(w, 1, cell); }

/* One joint move of two agents (glamas.gridworld.rules.step); returns the collisions (0 or 1). */
static int step(const World *w, Episode *e) {
    int i, collided;
    for (i = 0; i < 2; i++) {
        e->rewards[i] = 0.0;
        e->reached[i] = 0;
        e->new_cells[i] = e->done[i] ? e->cells[i] : w->next_cell[e->cells[i] * N_ACTIONS + e->actions[i]];
        if (!e->done[i]) e->rewards[i] = e->new_cells[i] == e->cells[i] ? w->bump : w->move;
    }
    collided = !e->done[0] && !e->done[1]
        && ((e->new_cells[0] == e->new_cells[1] && !goal_of_both(w, e->new_cells[0]))
            || (e->new_cells[0] == e->cells[1] && e->new_cells[1] == e->cells[0]));
    for (i = 0; i < 2; i++) {
        if (collided) {
            e->rewards[i] += w->collision;
            if (w->collision_replaces_move) e->rewards[i] = w->collision;
            e->new_cells[i] = w->bounce == BOUNCE_PREVIOUS ? e->cells[i] : w->starts[i];
        }
        if (!e->done[i] && is_goal_of(w, i, e->new_cells[i])) {
            e->reached[i] = 1;
            e->rewards[i] += w->goal;
        }
    }
    return collided;
}

/* Agents 0 on cell a and 1 on cell b playing action_a and action_b collide. */
static int would_collide(const World *w, int64_t a, int64_t b, int64_t action_a, int64_t action_b) {
    int64_t target_a = w->next_cell[a * N_ACTIONS + action_a], target_b = w->next_cell[b * N_ACTIONS + action_b];
    return (target_a == target_b && !goal_of_both(w, target_a)) || (target_a == b && target_b == a);
}

/* rules.could_collide: some joint action of agents on cells a and b collides. */
static int could_collide(const World *w, int64_t a, int64_t b) {
    for (int64_t action_a = 0; action_a < N_ACTIONS; action_a++)
        for (int64_t action_b = 0; action_b < N_ACTIONS; action_b++)
            if (would_collide(w, a, b, action_a, action_b)) return 1;
    return 0;
}

static void start_episode(const World *w, Episode *e) {
    memset(e, 0, sizeof *e);
    e->cells[0] = w->starts[0];
    e->cells[1] = w->starts[1];
}

static void end_step(Episode *e, int64_t t, int collisions) {
    e->acc[COLLISIONS] += collisions;
    for (int i = 0; i < 2; i++) {
        if (e->done[i]) continue;
        e->acc[REWARD + i] += e->rewards[i];
        if (e->reached[i]) { e->acc[STEPS + i] = (double)t; e->done[i] = 1; }
        e->cells[i] = e->new_cells[i];
    }
}

/* Add the episode to the mean of its block; ``row`` follows the episodes through the edges. */
static void end_episode(Episode *e, int64_t t, double *log, const int64_t *edges, int64_t episode, int64_t *row) {
    double width;
    e->acc[LENGTH] = (double)t;
    for (int i = 0; i < 2; i++)
        if (!e->done[i]) { e->acc[STEPS + i] = (double)t; e->acc[CAPPED] = 1.0; }
    while (episode >= edges[*row + 1]) (*row)++;
    width = (double)(edges[*row + 1] - edges[*row]);
    for (int k = 0; k < N_COLUMNS; k++) log[*row * N_COLUMNS + k] += e->acc[k] / width;
}

static int running(const Episode *e, int64_t t, int64_t max_steps) { return t < max_steps && !(e->done[0] && e->done[1]); }

/* Independent learners: a (cells x 4) table per agent over its own cell. */
void run_independent(const World *w, double alpha, double gamma, double exploit, int64_t n_episodes,
                     const int64_t *edges, int64_t max_steps, double *q, double *log, uint64_t *s) {
    Episode e;
    int64_t row = 0;
    for (int64_t episode = 0; episode < n_episodes; episode++) {
        int64_t t = 0;
        start_episode(w, &e);
        while (running(&e, t, max_steps)) {
            for (int i = 0; i < 2; i++)
                if (!e.done[i]) e.actions[i] = epsilon_greedy(q + (i * w->n_cells + e.cells[i]) * N_ACTIONS, N_ACTIONS, exploit, s);
            int collisions = step(w, &e);
            for (int i = 0; i < 2; i++)
                if (!e.done[i])
                    q_update(q + i * w->n_cells * N_ACTIONS, N_ACTIONS, e.cells[i], e.actions[i], e.rewards[i],
                             e.new_cells[i], e.reached[i], alpha, gamma);
            end_step(&e, ++t, collisions);
        }
        end_episode(&e, t, log, edges, episode, &row);
    }
}

/* Joint-state learners: a (cells^2 x 4) table per agent over both agents' cells. */
void run_joint_state(const World *w, double alpha, double gamma, double exploit, int64_t n_episodes,
                     const int64_t *edges, int64_t max_steps, double *q, double *log, uint64_t *s) {
    Episode e;
    int64_t row = 0, states = w->n_cells * w->n_cells;
    for (int64_t episode = 0; episode < n_episodes; episode++) {
        int64_t t = 0;
        start_episode(w, &e);
        while (running(&e, t, max_steps)) {
            int64_t joint = e.cells[0] * w->n_cells + e.cells[1];
            for (int i = 0; i < 2; i++)
                if (!e.done[i]) e.actions[i] = epsilon_greedy(q + (i * states + joint) * N_ACTIONS, N_ACTIONS, exploit, s);
            int collisions = step(w, &e);
            int64_t joint_next = e.new_cells[0] * w->n_cells + e.new_cells[1];
            for (int i = 0; i < 2; i++)
                if (!e.done[i])
                    q_update(q + i * states * N_ACTIONS, N_ACTIONS, joint, e.actions[i], e.rewards[i], joint_next,
                             e.reached[i], alpha, gamma);
            end_step(&e, ++t, collisions);
        }
        end_episode(&e, t, log, edges, episode, &row);
    }
}

/* The MMDP learner: one (cells^2 x 16) table over joint cells and joint actions, shared reward. */
void run_mmdp(const World *w, double alpha, double gamma, double exploit, int64_t n_episodes,
              const int64_t *edges, int64_t max_steps, double *q, double *log, uint64_t *s) {
    enum { JOINT_ACTIONS = N_ACTIONS * N_ACTIONS };
    Episode e;
    int64_t row = 0;
    for (int64_t episode = 0; episode < n_episodes; episode++) {
        int64_t t = 0;
        start_episode(w, &e);
        while (running(&e, t, max_steps)) {
            int64_t joint = e.cells[0] * w->n_cells + e.cells[1];
            int64_t action = epsilon_greedy(q + joint * JOINT_ACTIONS, JOINT_ACTIONS, exploit, s);
            e.actions[0] = action / N_ACTIONS;
            e.actions[1] = action % N_ACTIONS;
            int collisions = step(w, &e);
            int finished = (e.done[0] || e.reached[0]) && (e.done[1] || e.reached[1]);
            double shared = 0.0;  /* rules.shared_reward: the step rewards summed, the goal reward once both are in */
            int any_reached = 0;
            for (int i = 0; i < 2; i++) {
                shared += e.rewards[i];
                if (e.reached[i]) { shared -= w->goal; any_reached = 1; }
            }
            if (finished && any_reached) shared += w->goal;
            q_update(q, JOINT_ACTIONS, joint, action, shared, e.new_cells[0] * w->n_cells + e.new_cells[1],
                     finished, alpha, gamma);
            end_step(&e, ++t, collisions);
        }
        end_episode(&e, t, log, edges, episode, &row);
    }
}

/* GLA (eq. 12-15) with two actions over a context of two inputs, h = clip to [-L, L]. */
typedef struct { double rate, temperature, K, L; } GLAParams;

static double bound(double eta, double L) { return eta >= L ? L : eta <= -L ? -L : eta; }

static int64_t gla_act(const double *u, const double *x, const GLAParams *p, double *probs, uint64_t *s) {
    double largest = -INFINITY, total = 0.0, r;
    for (int i = 0; i < 2; i++) {
        double z = 0.0;
        for (int k = 0; k < 2; k++) z += x[k] * bound(u[i * 2 + k], p->L);
        probs[i] = z / p->temperature;
        if (probs[i] > largest) largest = probs[i];
    }
    for (int i = 0; i < 2; i++) {  /* exp(0) is 1 exactly: no exp for the largest, as glamas.gla.boltzmann */
        double shifted = probs[i] - largest;
        probs[i] = shifted == 0.0 ? 1.0 : exp(shifted);
        total += probs[i];
    }
    for (int i = 0; i < 2; i++) probs[i] /= total;
    r = uniform(s);
    return r < probs[0] ? 0 : 1;
}

static void gla_update(double *u, const double *x, int64_t action, double beta, const GLAParams *p, const double *probs) {
    for (int j = 0; j < 2; j++) {
        double indicator = j == action ? 1.0 : 0.0;
        for (int k = 0; k < 2; k++) {
            double gradient = x[k] / p->temperature * (indicator - probs[j]);
            double h = bound(u[j * 2 + k], p->L);
            u[j * 2 + k] += p->rate * beta * gradient + p->rate * p->K * (h - u[j * 2 + k]);
        }
    }
}

/* 2observe (Alg. 4), need "in range": u (2 agents x 2 actions x 2 inputs), the u_initial it drew, need_counts (deltas x 2).
 * Like the kernel, it tabulates could_collide for every pair of cells once per run. */
void run_two_observe(const World *w, double alpha, double gamma, double exploit, double rate, double temperature,
                     double K, double L, double init_range, const double *table, double penalty,
                     int64_t n_episodes, const int64_t *edges, int64_t max_steps, double *q, double *u,
                     double *u_initial, double *need_counts, double *log, uint64_t *s) {
    GLAParams p = {rate, temperature, K, L};
    Episode e;
    int64_t row = 0, choices[2], preferred[2], delta = 0;
    double x[2] = {0.0, 1.0}, probs[2][2];
    int observing, both = 0, needed = 0;
    uint8_t *in_range = malloc((size_t)(w->n_cells * w->n_cells));
    for (int64_t a = 0; a < w->n_cells; a++)
        for (int64_t b = 0; b < w->n_cells; b++) in_range[a * w->n_cells + b] = (uint8_t)could_collide(w, a, b);
    for (int k = 0; k < 8; k++) u_initial[k] = u[k] = init_range * (2.0 * uniform(s) - 1.0);
    for (int64_t episode = 0; episode < n_episodes; episode++) {
        int64_t t = 0;
        start_episode(w, &e);
        while (running(&e, t, max_steps)) {
            observing = !(e.done[0] || e.done[1]);
            if (observing) {
                delta = llabs(e.cells[0] / w->n_cols - e.cells[1] / w->n_cols)
                        + llabs(e.cells[0] % w->n_cols - e.cells[1] % w->n_cols);
                x[0] = (double)delta;
                for (int i = 0; i < 2; i++) choices[i] = gla_act(u + i * 4, x, &p, probs[i], s);
                for (int i = 0; i < 2; i++)
                    preferred[i] = epsilon_greedy(q + (i * w->n_cells + e.cells[i]) * N_ACTIONS, N_ACTIONS, exploit, s);
                int coming = would_collide(w, e.cells[0], e.cells[1], preferred[0], preferred[1]);
                both = choices[0] == 1 && choices[1] == 1;
                e.actions[0] = preferred[0];
                e.actions[1] = preferred[1];
                if (both && coming) {  /* one agent, picked at random, yields with a random other action */
                    int64_t yielder = integer(s, 2), other = integer(s, 3);
                    e.actions[yielder] = other >= preferred[yielder] ? other + 1 : other;
                }
                needed = in_range[e.cells[0] * w->n_cells + e.cells[1]];
                if (both) e.acc[COORDINATIONS] += 1.0;
            } else {
                for (int i = 0; i < 2; i++)
                    if (!e.done[i]) e.actions[i] = epsilon_greedy(q + (i * w->n_cells + e.cells[i]) * N_ACTIONS, N_ACTIONS, exploit, s);
            }
            int collisions = step(w, &e);
            if (observing) need_counts[delta * 2 + needed] += 2.0;  /* both agents observe */
            for (int i = 0; i < 2; i++)
                if (!e.done[i])
                    q_update(q + i * w->n_cells * N_ACTIONS, N_ACTIONS, e.cells[i], e.actions[i], e.rewards[i],
                             e.new_cells[i], e.reached[i], alpha, gamma);
            if (observing)
                for (int i = 0; i < 2; i++) {
                    double beta = table[choices[i] * 2 + needed];
                    if (both && !needed) beta -= penalty * (double)delta;
                    gla_update(u + i * 4, x, choices[i], beta, &p, probs[i]);
                }
            end_step(&e, ++t, collisions);
        }
        end_episode(&e, t, log, edges, episode, &row);
    }
    free(in_range);
}
