# Non-linear paper (Table 1): equilibrium run of the 3-D ideal DPD fluid (m = 1, rc = 1, a = 0,
# kT = 0.1, gamma0 = 5, gamma1 = 1; Ref: friction none, gamma1 = 0) at n = 16, dt = 1e-3
# (Appendix B). Records the speed histogram (MB check, eq. 53: 150 bins on [0, 2]) and the
# off-diagonal pressure every step (Einstein-Helfand, eq. 59).
# Same script in both engines:  dpdnl run in.eq -var friction dot -var noise corrected -var gamma1 1.0
#                               build/lmp_dpdnl -in in.eq -var friction dot ...
units           lj
dimension       3
boundary        p p p
atom_style      atomic
comm_modify     vel yes

variable        friction index none
variable        noise    index plain
variable        gamma1   index 0.0
variable        n        index 16
variable        N        index 4000
variable        eq       index 2000
variable        steps    index 40000
variable        seed     index 34387
variable        L        equal (${N}/${n})^(1.0/3.0)
region          box block 0 ${L} 0 ${L} 0 ${L}
create_box      1 box
create_atoms    1 random ${N} 8675 box
mass            1 1.0
velocity        all create 0.1 4928 mom yes dist gaussian

pair_style      dpd/nonlinear 0.1 1.0 ${seed} friction ${friction} noise ${noise}
pair_coeff      1 1 0.0 5.0 ${gamma1}
neighbor        0.3 bin
neigh_modify    delay 0 every 1 check yes
timestep        0.001
fix             1 all nve
thermo          1000
run             ${eq}

reset_timestep  0
fix             press all ave/time 1 1 1 c_thermo_press[4] c_thermo_press[5] c_thermo_press[6] file press.ave
variable        speed atom sqrt(vx*vx+vy*vy+vz*vz)
fix             hist all ave/histo 10 100 1000 0.0 2.0 150 v_speed mode vector file speed.histo
fix             temp all ave/time 10 100 1000 c_thermo_temp file temp.ave
thermo_style    custom step temp press pxy pxz pyz
run             ${steps}
