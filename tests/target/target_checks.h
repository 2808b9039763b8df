/*
 * The checks of the target test program. Each prints one line per check
 * through the port console ("PASS ..." / "FAIL ...", "info ..." for
 * figures) and returns the number that failed. They are registered in the
 * table target_checks[] of target_main.c.
 */
#ifndef PDT_TARGET_CHECKS_H
#define PDT_TARGET_CHECKS_H

/* check_vectors.c: the generated vectors of tests/vectors/. */
int target_check_fft(void);
int target_check_model(void);
int target_check_discrete(void);
int target_check_cost(void);

/* check_ident.c: identification of simulated plants, and the work of one
 * cost evaluation at N = 2000. */
int target_check_ident(void);
int target_check_cost_work(void);

/* check_pid.c: the PID's scenarios and the work of one update. */
int target_check_pid(void);

#endif /* PDT_TARGET_CHECKS_H */
